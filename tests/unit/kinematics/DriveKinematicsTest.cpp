#include "firmware/kinematics/DriveKinematics.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

// Wheel speeds are floats: allow float rounding on values of order 10.
constexpr double kWheelTol = 1e-5;
constexpr double kTwistTol = 1e-6;

enum Wheel { FL = 0, FR = 1, RL = 2, RR = 3 };

// r = 0.1 m, wheelbase 0.4 m, track 0.3 m: lx = 0.2, ly = 0.15, l = lx + ly = 0.35 m.
DriveKinematics mecanum() {
  return DriveKinematics(DriveGeometry{DriveType::Mecanum, 0.1, 0.4, 0.3});
}
// r = 0.1 m, track 0.4 m (wheelbase unused).
DriveKinematics differential() {
  return DriveKinematics(DriveGeometry{DriveType::Differential, 0.1, 0.0, 0.4});
}

void expect_wheels(const float* w, double fl, double fr, double rl, double rr) {
  EXPECT_NEAR(w[FL], fl, kWheelTol);
  EXPECT_NEAR(w[FR], fr, kWheelTol);
  EXPECT_NEAR(w[RL], rl, kWheelTol);
  EXPECT_NEAR(w[RR], rr, kWheelTol);
}

TEST(MecanumKinematicsTest, Shape) {
  const DriveKinematics k = mecanum();
  EXPECT_EQ(k.wheel_count(), 4);
  EXPECT_EQ(k.type(), DriveType::Mecanum);
  EXPECT_TRUE(k.holonomic());
}

TEST(MecanumKinematicsTest, PureForward) {
  float w[4] = {};
  mecanum().inverse({1.0, 0.0, 0.0}, w);
  expect_wheels(w, 10, 10, 10, 10);  // 1 m/s / 0.1 m
}

TEST(MecanumKinematicsTest, PureSidewaysLeft) {
  float w[4] = {};
  mecanum().inverse({0.0, 1.0, 0.0}, w);
  expect_wheels(w, -10, 10, 10, -10);
}

TEST(MecanumKinematicsTest, PureRotationCounterClockwise) {
  float w[4] = {};
  mecanum().inverse({0.0, 0.0, 1.0}, w);
  // Each wheel's rim speed is wz * l = 0.35 m/s: 3.5 rad/s, left side backwards.
  expect_wheels(w, -3.5, 3.5, -3.5, 3.5);
}

TEST(MecanumKinematicsTest, SuperpositionOfComponents) {
  float w[4] = {};
  mecanum().inverse({0.5, -0.2, 0.4}, w);
  // 5 * forward + (-0.2) * sideways + 0.4 * rotation, from the three cases above.
  expect_wheels(w, 5 + 2 - 1.4, 5 - 2 + 1.4, 5 - 2 - 1.4, 5 + 2 + 1.4);
}

TEST(MecanumKinematicsTest, ForwardOfConsistentSpeeds) {
  const DriveKinematics k = mecanum();
  const float fwd[4] = {10, 10, 10, 10};
  Twist t = k.forward(fwd);
  EXPECT_NEAR(t.vx, 1.0, kTwistTol);
  EXPECT_NEAR(t.vy, 0.0, kTwistTol);
  EXPECT_NEAR(t.wz, 0.0, kTwistTol);
  const float side[4] = {-10, 10, 10, -10};
  t = k.forward(side);
  EXPECT_NEAR(t.vx, 0.0, kTwistTol);
  EXPECT_NEAR(t.vy, 1.0, kTwistTol);
  EXPECT_NEAR(t.wz, 0.0, kTwistTol);
  const float rot[4] = {-3.5F, 3.5F, -3.5F, 3.5F};
  t = k.forward(rot);
  EXPECT_NEAR(t.vx, 0.0, kTwistTol);
  EXPECT_NEAR(t.vy, 0.0, kTwistTol);
  EXPECT_NEAR(t.wz, 1.0, kTwistTol);
}

TEST(MecanumKinematicsTest, RoundTrip) {
  const DriveKinematics k = mecanum();
  const Twist want{0.37, -0.81, 1.23};
  float w[4] = {};
  k.inverse(want, w);
  const Twist got = k.forward(w);
  EXPECT_NEAR(got.vx, want.vx, kTwistTol);
  EXPECT_NEAR(got.vy, want.vy, kTwistTol);
  EXPECT_NEAR(got.wz, want.wz, kTwistTol);
}

TEST(MecanumKinematicsTest, InconsistentSpeedsGiveLeastSquaresTwist) {
  const DriveKinematics k = mecanum();
  // Only the front-left wheel turns, at 10 rad/s: no rigid motion does that.
  // By hand, with rows a_FL = (1, -1, -l), a_FR = (1, 1, l), a_RL = (1, 1, -l),
  // a_RR = (1, -1, l) (times 1/r): the columns are orthogonal, so the least-squares twist is
  // each column's projection: vx = r*10/4 = 0.25, vy = -r*10/4 = -0.25,
  // wz = -r*10/(4 l) = -1/1.4 = -0.714285...
  const float w[4] = {10, 0, 0, 0};
  const Twist t = k.forward(w);
  EXPECT_NEAR(t.vx, 0.25, kTwistTol);
  EXPECT_NEAR(t.vy, -0.25, kTwistTol);
  EXPECT_NEAR(t.wz, -0.7142857142857143, kTwistTol);
  // The fitted twist drives the wheels at (7.5, -2.5, 2.5, 2.5), leaving the residual
  // (2.5, 2.5, -2.5, -2.5), which must be orthogonal to every column of the inverse map
  // (the normal equations), checked here through inverse() rather than by formula.
  float fit[4] = {};
  k.inverse(t, fit);
  expect_wheels(fit, 7.5, -2.5, 2.5, 2.5);
  const double res[4] = {w[0] - fit[0], w[1] - fit[1], w[2] - fit[2], w[3] - fit[3]};
  const Twist unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const Twist& u : unit) {
    float col[4] = {};
    k.inverse(u, col);
    double dot = 0;
    for (int i = 0; i < 4; ++i) dot += res[i] * double(col[i]);
    EXPECT_NEAR(dot, 0.0, 1e-4);
  }
}

TEST(MecanumKinematicsTest, ForwardDeltaIsDisplacement) {
  const DriveKinematics k = mecanum();
  // Every wheel turned 5 rad: 0.5 m forward.
  const double fwd[4] = {5, 5, 5, 5};
  const Twist d = k.forward_delta(fwd);
  EXPECT_NEAR(d.vx, 0.5, 1e-12);
  EXPECT_NEAR(d.vy, 0.0, 1e-12);
  EXPECT_NEAR(d.wz, 0.0, 1e-12);
}

TEST(DifferentialKinematicsTest, Shape) {
  const DriveKinematics k = differential();
  EXPECT_EQ(k.wheel_count(), 2);
  EXPECT_EQ(k.type(), DriveType::Differential);
  EXPECT_FALSE(k.holonomic());
}

TEST(DifferentialKinematicsTest, Forward) {
  float w[2] = {};
  differential().inverse({1.0, 0.0, 0.0}, w);
  EXPECT_NEAR(w[0], 10.0, kWheelTol);
  EXPECT_NEAR(w[1], 10.0, kWheelTol);
}

TEST(DifferentialKinematicsTest, RotationLeftBackRightForward) {
  float w[2] = {};
  differential().inverse({0.0, 0.0, 1.0}, w);
  // Rim speed wz * track / 2 = 0.2 m/s -> 2 rad/s.
  EXPECT_NEAR(w[0], -2.0, kWheelTol);
  EXPECT_NEAR(w[1], 2.0, kWheelTol);
}

TEST(DifferentialKinematicsTest, InverseIgnoresVy) {
  const DriveKinematics k = differential();
  float a[2] = {}, b[2] = {};
  k.inverse({0.3, 0.0, -0.5}, a);
  k.inverse({0.3, 5.0, -0.5}, b);
  EXPECT_EQ(a[0], b[0]);
  EXPECT_EQ(a[1], b[1]);
  // Left: (0.3 + 0.2 * 0.5) / 0.1 = 4; right: (0.3 - 0.1) / 0.1 = 2.
  EXPECT_NEAR(a[0], 4.0, kWheelTol);
  EXPECT_NEAR(a[1], 2.0, kWheelTol);
}

TEST(DifferentialKinematicsTest, ForwardHasNoVy) {
  const DriveKinematics k = differential();
  const float w[2] = {4.0F, 2.0F};
  const Twist t = k.forward(w);
  // v = r * (wl + wr) / 2 = 0.3; wz = r * (wr - wl) / track = 0.1 * -2 / 0.4 = -0.5.
  EXPECT_NEAR(t.vx, 0.3, kTwistTol);
  EXPECT_EQ(t.vy, 0.0);
  EXPECT_NEAR(t.wz, -0.5, kTwistTol);
}

TEST(DifferentialKinematicsTest, RoundTrip) {
  const DriveKinematics k = differential();
  const Twist want{-0.42, 0.0, 0.77};
  float w[2] = {};
  k.inverse(want, w);
  const Twist got = k.forward(w);
  EXPECT_NEAR(got.vx, want.vx, kTwistTol);
  EXPECT_EQ(got.vy, 0.0);
  EXPECT_NEAR(got.wz, want.wz, kTwistTol);
}

TEST(DifferentialKinematicsTest, WritesOnlyTwoWheels) {
  float w[4] = {-1, -1, 99, 99};
  differential().inverse({1.0, 0.0, 0.0}, w);
  EXPECT_EQ(w[2], 99.0F);
  EXPECT_EQ(w[3], 99.0F);
}

}  // namespace
}  // namespace carril::fw
