#include "firmware/control/MotionLimiter.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::fw {
namespace {

constexpr double kDt = 0.01;  // [s]

// Limits with everything but the one under test out of the way.
MotionLimits loose() {
  MotionLimits l;
  l.max_speed_mps = 100.0;
  l.max_yaw_rate_radps = 100.0;
  l.max_accel_mps2 = 1e6;
  l.max_yaw_accel_radps2 = 1e6;
  l.max_wheel_speed_radps = 1e6;
  return l;
}

DriveKinematics mecanum() {
  return DriveKinematics(DriveGeometry{DriveType::Mecanum, 0.1, 0.4, 0.3});
}
DriveKinematics differential() {
  return DriveKinematics(DriveGeometry{DriveType::Differential, 0.1, 0.0, 0.4});
}

TEST(MotionLimiterTest, PassesFeasibleTwist) {
  const DriveKinematics kin = mecanum();
  MotionLimiter lim(loose(), kin, kDt);
  float w[4] = {};
  const Twist t = lim.apply({0.5, -0.2, 0.4}, w);
  EXPECT_DOUBLE_EQ(t.vx, 0.5);
  EXPECT_DOUBLE_EQ(t.vy, -0.2);
  EXPECT_DOUBLE_EQ(t.wz, 0.4);
  // Wheel speeds of that twist (see DriveKinematicsTest): FL 5+2-1.4, FR 5-2+1.4, ...
  EXPECT_NEAR(w[0], 5.6, 1e-5);
  EXPECT_NEAR(w[1], 4.4, 1e-5);
  EXPECT_NEAR(w[2], 1.6, 1e-5);
  EXPECT_NEAR(w[3], 8.4, 1e-5);
}

TEST(MotionLimiterTest, SpeedCapOnTranslationalNorm) {
  const DriveKinematics kin = mecanum();
  MotionLimits l = loose();
  l.max_speed_mps = 1.0;
  MotionLimiter lim(l, kin, kDt);
  float w[4] = {};
  // |(3, 4)| = 5 -> scaled to norm 1 along the same direction.
  const Twist t = lim.apply({3.0, 4.0, 0.2}, w);
  EXPECT_NEAR(t.vx, 0.6, 1e-12);
  EXPECT_NEAR(t.vy, 0.8, 1e-12);
  EXPECT_DOUBLE_EQ(t.wz, 0.2);  // yaw rate is not part of the speed cap
}

TEST(MotionLimiterTest, YawRateCap) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_yaw_rate_radps = 1.5;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  EXPECT_DOUBLE_EQ(lim.apply({0.0, 0.0, 5.0}, w).wz, 1.5);
  EXPECT_DOUBLE_EQ(lim.apply({0.0, 0.0, -5.0}, w).wz, -1.5);
  EXPECT_DOUBLE_EQ(lim.apply({0.0, 0.0, 1.0}, w).wz, 1.0);
}

TEST(MotionLimiterTest, AccelerationLimitFromRest) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_accel_mps2 = 1.0;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  // 1 m/s^2 * 0.01 s = 0.01 m/s per call.
  EXPECT_NEAR(lim.apply({1.0, 0.0, 0.0}, w).vx, 0.01, 1e-12);
  EXPECT_NEAR(w[0], 0.1, 1e-6);  // wheels follow the limited twist
  EXPECT_NEAR(lim.apply({1.0, 0.0, 0.0}, w).vx, 0.02, 1e-12);
  EXPECT_NEAR(lim.last().vx, 0.02, 1e-12);
  // Braking is limited the same way.
  EXPECT_NEAR(lim.apply({0.0, 0.0, 0.0}, w).vx, 0.01, 1e-12);
}

TEST(MotionLimiterTest, AccelerationLimitIsOnTheVector) {
  const DriveKinematics kin = mecanum();
  MotionLimits l = loose();
  l.max_accel_mps2 = 1.0;
  MotionLimiter lim(l, kin, kDt);
  float w[4] = {};
  // Diagonal request: the 0.01 m/s step is split along the diagonal, 0.01 / sqrt(2) each.
  const Twist t = lim.apply({2.0, 2.0, 0.0}, w);
  EXPECT_NEAR(t.vx, 0.01 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(t.vy, 0.01 / std::sqrt(2.0), 1e-12);
}

TEST(MotionLimiterTest, YawAccelerationLimit) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_yaw_accel_radps2 = 3.0;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  EXPECT_NEAR(lim.apply({0.0, 0.0, 1.0}, w).wz, 0.03, 1e-12);
  EXPECT_NEAR(lim.apply({0.0, 0.0, 1.0}, w).wz, 0.06, 1e-12);
  EXPECT_NEAR(lim.apply({0.0, 0.0, -1.0}, w).wz, 0.03, 1e-12);
}

TEST(MotionLimiterTest, WheelSaturationScalesUniformly) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_wheel_speed_radps = 10.0;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  // vx = 1, wz = 2: left (1 - 0.2 * 2) / 0.1 = 6 rad/s, right (1 + 0.4) / 0.1 = 14 rad/s.
  // Scaled by 10/14: right at the limit, left 60/14, twist (10/14, 0, 20/14).
  const Twist t = lim.apply({1.0, 0.0, 2.0}, w);
  EXPECT_NEAR(w[1], 10.0, 1e-5);
  EXPECT_NEAR(w[0], 60.0 / 14.0, 1e-5);
  EXPECT_NEAR(t.vx, 10.0 / 14.0, 1e-12);
  EXPECT_NEAR(t.wz, 20.0 / 14.0, 1e-12);
  EXPECT_NEAR(t.wz / t.vx, 2.0, 1e-12);  // same curvature as requested
}

TEST(MotionLimiterTest, WheelSaturationMecanumKeepsDirection) {
  const DriveKinematics kin = mecanum();
  MotionLimits l = loose();
  l.max_wheel_speed_radps = 10.0;
  MotionLimiter lim(l, kin, kDt);
  float w[4] = {};
  // (1, 0.5, 0): FL = FR... = (1 -+ 0.5) / 0.1 -> peak 15 rad/s, scale 2/3.
  const Twist t = lim.apply({1.0, 0.5, 0.0}, w);
  EXPECT_NEAR(t.vx, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(t.vy, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(t.wz, 0.0, 1e-12);
  double peak = 0;
  for (float x : w) peak = std::fmax(peak, std::fabs(double(x)));
  EXPECT_NEAR(peak, 10.0, 1e-5);
}

TEST(MotionLimiterTest, DifferentialDropsVy) {
  const DriveKinematics kin = differential();
  MotionLimiter lim(loose(), kin, kDt);
  float w[2] = {};
  const Twist t = lim.apply({0.5, 0.7, 0.0}, w);
  EXPECT_DOUBLE_EQ(t.vx, 0.5);
  EXPECT_EQ(t.vy, 0.0);
  EXPECT_NEAR(w[0], 5.0, 1e-5);
  EXPECT_NEAR(w[1], 5.0, 1e-5);
}

TEST(MotionLimiterTest, DifferentialSpeedCapIgnoresDroppedVy) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_speed_mps = 1.0;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  // vy is dropped before the cap, so vx = 0.8 is not scaled by |(0.8, 5)|.
  EXPECT_DOUBLE_EQ(lim.apply({0.8, 5.0, 0.0}, w).vx, 0.8);
}

TEST(MotionLimiterTest, ResetStartsFromRest) {
  const DriveKinematics kin = differential();
  MotionLimits l = loose();
  l.max_accel_mps2 = 1.0;
  l.max_yaw_accel_radps2 = 3.0;
  MotionLimiter lim(l, kin, kDt);
  float w[2] = {};
  for (int i = 0; i < 30; ++i) lim.apply({1.0, 0.0, 1.0}, w);
  EXPECT_NEAR(lim.last().vx, 0.30, 1e-9);
  lim.reset();
  EXPECT_EQ(lim.last().vx, 0.0);
  EXPECT_EQ(lim.last().vy, 0.0);
  EXPECT_EQ(lim.last().wz, 0.0);
  const Twist t = lim.apply({1.0, 0.0, 1.0}, w);
  EXPECT_NEAR(t.vx, 0.01, 1e-12);
  EXPECT_NEAR(t.wz, 0.03, 1e-12);
}

}  // namespace
}  // namespace carril::fw
