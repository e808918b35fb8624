#include "firmware/mapping/Pose3Tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace carril::fw {
namespace {

constexpr double kDeg = kPi / 180.0;

TEST(Pose3TrackerTest, ZFollowsARampUpAndBackDown) {
  Pose3Tracker t;
  t.reset(Pose2{0.0, 0.0, 0.3}, 0.0);
  const double pitch = 5.0 * kDeg;
  // 2 m of horizontal travel along the heading 0.3 rad, in 1 cm ticks, nose up.
  for (int i = 1; i <= 200; ++i) {
    const double s = 0.01 * i;
    t.update(Pose2{s * std::cos(0.3), s * std::sin(0.3), 0.3}, 0.0F, float(pitch));
  }
  // The first tick averages level and 5 deg (the robot was level at reset): half a tick lost.
  EXPECT_NEAR(t.pose().z, 2.0 * std::tan(pitch), 0.001);
  EXPECT_NEAR(t.pose().pitch, pitch, 1e-6);
  // Reversing down the same ramp (still nose up) brings it back.
  for (int i = 199; i >= 0; --i) {
    const double s = 0.01 * i;
    t.update(Pose2{s * std::cos(0.3), s * std::sin(0.3), 0.3}, 0.0F, float(pitch));
  }
  EXPECT_NEAR(t.pose().z, 0.0, 0.001);
}

TEST(Pose3TrackerTest, NonFiniteAttitudeKeepsTheLastGoodValue) {
  Pose3Tracker t;
  t.reset(Pose2{}, 1.0);
  t.update(Pose2{0.1, 0.0, 0.0}, 0.02F, 0.05F);
  t.update(Pose2{0.2, 0.0, 0.0}, std::numeric_limits<float>::quiet_NaN(),
           std::numeric_limits<float>::infinity());
  EXPECT_FLOAT_EQ(float(t.pose().roll), 0.02F);
  EXPECT_FLOAT_EQ(float(t.pose().pitch), 0.05F);
  EXPECT_TRUE(std::isfinite(t.pose().z));
}

TEST(Pose3TrackerTest, SensorPoseOfAMountOnAPitchedRobot) {
  Pose3Tracker t;
  t.reset(Pose2{1.0, 2.0, kPi / 2}, 0.5);
  t.update(Pose2{1.0, 2.0, kPi / 2}, 0.0F, float(5.0 * kDeg));  // nose up, no motion
  SensorMount m;
  m.z_m = 0.7;
  const Pose3 s = t.sensor_pose(m);
  // Nose up tips the mast backwards: facing +y, backwards is -y.
  EXPECT_NEAR(s.x, 1.0, 1e-9);
  EXPECT_NEAR(s.y, 2.0 - 0.7 * std::sin(5.0 * kDeg), 1e-6);
  EXPECT_NEAR(s.z, 0.5 + 0.7 * std::cos(5.0 * kDeg), 1e-6);
  EXPECT_NEAR(s.pitch, 5.0 * kDeg, 1e-6);
  EXPECT_NEAR(s.yaw, kPi / 2, 1e-9);
  // A forward point of the sensor goes up when the nose is up.
  const Vec3 fwd = rotation_of(s.roll, s.pitch, s.yaw) * Vec3(1, 0, 0);
  EXPECT_GT(fwd.z(), 0.08);
  // Roll positive lifts the left side.
  const Vec3 left = rotation_of(0.1, 0.0, 0.0) * Vec3(0, 1, 0);
  EXPECT_GT(left.z(), 0.09);
}

TEST(Pose3TrackerTest, AttitudeRoundTrip) {
  for (double r : {-0.4, 0.0, 0.3})
    for (double p : {-0.5, 0.1, 0.6})
      for (double y : {-3.0, 0.0, 2.0}) {
        double r2 = 0, p2 = 0, y2 = 0;
        attitude_of(rotation_of(r, p, y), r2, p2, y2);
        EXPECT_NEAR(r2, r, 1e-9);
        EXPECT_NEAR(p2, p, 1e-9);
        EXPECT_NEAR(y2, y, 1e-9);
      }
}

}  // namespace
}  // namespace carril::fw
