#include "firmware/estimation/Odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::fw {
namespace {

constexpr double kR = 0.1;      // wheel radius [m]
constexpr double kTrack = 0.4;  // differential track [m]

DriveKinematics differential() {
  return DriveKinematics(DriveGeometry{DriveType::Differential, kR, 0.0, kTrack});
}
DriveKinematics mecanum() {
  return DriveKinematics(DriveGeometry{DriveType::Mecanum, kR, 0.4, 0.3});
}

hal::WheelFeedbackSet feedback(int n, const double* pos, const float* vel = nullptr) {
  hal::WheelFeedbackSet fb;
  fb.count = static_cast<std::uint8_t>(n);
  for (int i = 0; i < n; ++i) {
    fb.wheel[i].position_rad = pos[i];
    fb.wheel[i].velocity_radps = vel ? vel[i] : 0.0F;
  }
  return fb;
}

// Feeds `steps` evenly spaced encoder readings going from `start` to `start + total` (after a
// first reading at `start` that only primes the odometry).
void drive(Odometry& odo, int n, const double* start, const double* total, int steps) {
  double pos[hal::kMaxWheels] = {};
  for (int k = 0; k <= steps; ++k) {
    for (int i = 0; i < n; ++i) pos[i] = start[i] + total[i] * k / steps;
    odo.update(feedback(n, pos));
  }
}

TEST(OdometryTest, StartsAtOrigin) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  EXPECT_EQ(odo.pose().x, 0.0);
  EXPECT_EQ(odo.pose().y, 0.0);
  EXPECT_EQ(odo.pose().yaw, 0.0);
}

TEST(OdometryTest, FirstReadingOnlyLatches) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  const double pos[2] = {123.0, -45.0};  // encoders already far from zero at start
  odo.update(feedback(2, pos));
  EXPECT_EQ(odo.pose().x, 0.0);
  EXPECT_EQ(odo.pose().y, 0.0);
  EXPECT_EQ(odo.pose().yaw, 0.0);
}

TEST(OdometryTest, DifferentialStraightOneMetre) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  const double start[2] = {3.0, -7.0};
  const double total[2] = {10.0, 10.0};  // 10 rad * 0.1 m = 1 m
  drive(odo, 2, start, total, 100);
  EXPECT_NEAR(odo.pose().x, 1.0, 1e-9);
  EXPECT_NEAR(odo.pose().y, 0.0, 1e-9);
  EXPECT_NEAR(odo.pose().yaw, 0.0, 1e-9);
}

TEST(OdometryTest, DifferentialRotationInPlace) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  // Quarter turn: each wheel rolls (pi/2) * track/2 = 0.1 pi m, i.e. pi rad.
  const double a = (kPi / 2) * (kTrack / 2) / kR;
  const double start[2] = {0.0, 0.0};
  const double total[2] = {-a, a};
  drive(odo, 2, start, total, 50);
  EXPECT_NEAR(odo.pose().yaw, kPi / 2, 1e-9);
  EXPECT_NEAR(odo.pose().x, 0.0, 1e-9);
  EXPECT_NEAR(odo.pose().y, 0.0, 1e-9);
}

TEST(OdometryTest, YawWrapsToMinusPiPi) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  // Three quarter turns counter-clockwise end at -pi/2.
  const double a = 3 * (kPi / 2) * (kTrack / 2) / kR;
  const double start[2] = {0.0, 0.0};
  const double total[2] = {-a, a};
  drive(odo, 2, start, total, 90);
  EXPECT_NEAR(odo.pose().yaw, -kPi / 2, 1e-9);
}

TEST(OdometryTest, DifferentialQuarterCircleArc) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  // Left turn on a circle of radius R = 1 m centred at (0, R): the left wheel runs on radius
  // R - track/2 = 0.8 m, the right on R + track/2 = 1.2 m. Over a quarter circle they roll
  // 0.8 * pi/2 and 1.2 * pi/2 metres: 4 pi and 6 pi rad. The end pose is (R, R, pi/2).
  const double R = 1.0;
  const double start[2] = {0.0, 0.0};
  const double total[2] = {(R - kTrack / 2) * (kPi / 2) / kR, (R + kTrack / 2) * (kPi / 2) / kR};
  EXPECT_NEAR(total[0], 4 * kPi, 1e-12);
  EXPECT_NEAR(total[1], 6 * kPi, 1e-12);
  drive(odo, 2, start, total, 200);
  EXPECT_NEAR(odo.pose().x, R, 1e-3);
  EXPECT_NEAR(odo.pose().y, R, 1e-3);
  EXPECT_NEAR(odo.pose().yaw, kPi / 2, 1e-3);
}

TEST(OdometryTest, MecanumSidewaysOneMetre) {
  const DriveKinematics kin = mecanum();
  Odometry odo(kin);
  const double start[4] = {0.0, 0.0, 0.0, 0.0};
  // Sideways left: FL and RR backwards, FR and RL forwards, 10 rad each.
  const double total[4] = {-10.0, 10.0, 10.0, -10.0};
  drive(odo, 4, start, total, 100);
  EXPECT_NEAR(odo.pose().x, 0.0, 1e-9);
  EXPECT_NEAR(odo.pose().y, 1.0, 1e-9);
  EXPECT_NEAR(odo.pose().yaw, 0.0, 1e-9);
}

TEST(OdometryTest, DisplacementIsRotatedIntoOdomFrame) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  // Turn +90 deg in place, then drive 0.5 m straight: the robot ends at (0, 0.5).
  const double a = (kPi / 2) * (kTrack / 2) / kR;
  const double s0[2] = {0.0, 0.0};
  const double turn[2] = {-a, a};
  drive(odo, 2, s0, turn, 20);
  const double s1[2] = {-a, a};
  const double fwd[2] = {5.0, 5.0};
  drive(odo, 2, s1, fwd, 20);
  EXPECT_NEAR(odo.pose().x, 0.0, 1e-9);
  EXPECT_NEAR(odo.pose().y, 0.5, 1e-9);
  EXPECT_NEAR(odo.pose().yaw, kPi / 2, 1e-9);
}

TEST(OdometryTest, TwistFromWheelSpeeds) {
  const DriveKinematics kin = differential();
  Odometry odo(kin);
  const double pos[2] = {0.0, 0.0};
  const float vel[2] = {4.0F, 6.0F};
  odo.update(feedback(2, pos, vel));
  // v = 0.1 * (4 + 6) / 2 = 0.5 m/s; wz = 0.1 * (6 - 4) / 0.4 = 0.5 rad/s.
  EXPECT_NEAR(odo.twist().vx, 0.5, 1e-6);
  EXPECT_NEAR(odo.twist().vy, 0.0, 1e-12);
  EXPECT_NEAR(odo.twist().wz, 0.5, 1e-6);
}

TEST(OdometryTest, IgnoresShortFeedback) {
  const DriveKinematics kin = mecanum();
  Odometry odo(kin);
  const double zero[4] = {0, 0, 0, 0};
  odo.update(feedback(4, zero));
  const double moved[4] = {10, 10, 10, 10};
  odo.update(feedback(2, moved));  // only two wheels reported: not usable
  EXPECT_EQ(odo.pose().x, 0.0);
  odo.update(feedback(4, moved));
  EXPECT_NEAR(odo.pose().x, 1.0, 1e-9);
}

hal::ImuSample gyro(hal::TimeNs t_ns, double rate_radps, bool valid = true) {
  hal::ImuSample s;
  s.stamp_ns = t_ns;
  s.valid = valid;
  s.yaw_rate_radps = float(rate_radps);
  return s;
}

constexpr hal::TimeNs kStepNs = 10'000'000;  // 100 Hz

// A slipping wheel: the encoders claim the robot turned while it drove straight; the gyro says
// it did not. The heading follows the gyro and the metre driven stays on the x axis.
TEST(OdometryTest, GyroHeadingIgnoresAWheelsSlip) {
  const DriveKinematics kin = differential();
  Odometry wheels(kin, false), fused(kin, true);
  double pos[2] = {0.0, 0.0};
  for (int k = 0; k <= 100; ++k) {
    // The right wheel reads 5 % more than it rolled.
    pos[0] = 10.0 * k / 100;
    pos[1] = 10.5 * k / 100;
    wheels.update(feedback(2, pos), gyro(k * kStepNs, 0.0));
    fused.update(feedback(2, pos), gyro(k * kStepNs, 0.0));
  }
  EXPECT_NEAR(wheels.pose().yaw, 0.5 * kR / kTrack, 1e-9);  // 0.125 rad from the slip
  EXPECT_GT(std::fabs(wheels.pose().y), 0.05);
  EXPECT_NEAR(fused.pose().yaw, 0.0, 1e-12);
  EXPECT_NEAR(fused.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(fused.pose().x, 1.025, 1e-9);  // the translation is still the wheels'
  EXPECT_EQ(fused.gyro_steps(), 100U);
  EXPECT_EQ(wheels.gyro_steps(), 0U);
}

// The yaw rate is integrated over the samples' own interval (trapezoid): a sample that did not
// change since the last step adds nothing, and the next one integrates the whole interval.
TEST(OdometryTest, GyroIntegratesOverTheSampleInterval) {
  const DriveKinematics kin = differential();
  Odometry odo(kin, true);
  const double still[2] = {0.0, 0.0};
  odo.update(feedback(2, still), gyro(0, 1.0));
  odo.update(feedback(2, still), gyro(kStepNs, 1.0));
  EXPECT_NEAR(odo.pose().yaw, 0.01, 1e-9);
  // Stale: the same sample again, while the wheels say the robot turned. The gyro's heading
  // waits for its next sample; the wheels' turn is not taken.
  const double turned[2] = {-0.02, 0.02};
  odo.update(feedback(2, turned), gyro(kStepNs, 1.0));
  EXPECT_NEAR(odo.pose().yaw, 0.01, 1e-9);
  EXPECT_EQ(odo.gyro_steps(), 2U);
  odo.update(feedback(2, turned), gyro(3 * kStepNs, 2.0));  // 20 ms from 1 to 2 rad/s
  EXPECT_NEAR(odo.pose().yaw, 0.01 + 0.03, 1e-7);
}

// No good sample (invalid, NaN, or after a gap longer than kMaxGyroGapNs): the step's heading
// change is the wheels', and the gyro takes over again from the next good pair of samples.
TEST(OdometryTest, WithoutAGoodGyroSampleTheWheelsTurnTheHeading) {
  const DriveKinematics kin = differential();
  const double a = 0.01 * (kTrack / 2) / kR;  // a wheel turn of 0.01 rad of heading per step
  double pos[2] = {0.0, 0.0};
  Odometry odo(kin, true);
  hal::TimeNs t = 0;
  const auto step = [&](const hal::ImuSample& s) {
    pos[0] -= a;
    pos[1] += a;
    odo.update(feedback(2, pos), s);
  };
  odo.update(feedback(2, pos), gyro(t, 0.0));
  step(gyro(t += kStepNs, 0.0));  // gyro: no turn
  EXPECT_NEAR(odo.pose().yaw, 0.0, 1e-12);
  step(gyro(t += kStepNs, 0.0, false));  // invalid: the wheels' 0.01
  EXPECT_NEAR(odo.pose().yaw, 0.01, 1e-9);
  step(gyro(t += kStepNs, std::nan("")));  // NaN: the wheels'
  EXPECT_NEAR(odo.pose().yaw, 0.02, 1e-9);
  step(gyro(t += kStepNs, 0.0));  // the first good sample again only primes
  EXPECT_NEAR(odo.pose().yaw, 0.03, 1e-9);
  step(gyro(t += kStepNs, 0.0));  // the gyro again
  EXPECT_NEAR(odo.pose().yaw, 0.03, 1e-9);
  step(gyro(t += Odometry::kMaxGyroGapNs + 1, 0.0));  // too long a gap: the wheels'
  EXPECT_NEAR(odo.pose().yaw, 0.04, 1e-9);
  EXPECT_EQ(odo.gyro_steps(), 2U);
  EXPECT_EQ(odo.wheel_steps(), 5U);  // the priming step included
}

}  // namespace
}  // namespace carril::fw
