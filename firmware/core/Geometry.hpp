#pragma once
// Fixed-size Eigen types used for geometry and kinematics (never heap-allocated).
#include <Eigen/Core>
#include <cmath>

namespace carril::fw {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double kPi = 3.14159265358979323846;

// Body-frame velocity: x forward, y left, yaw counter-clockwise.
struct Twist {
  double vx = 0.0;  // [m/s]
  double vy = 0.0;  // [m/s]
  double wz = 0.0;  // [rad/s]
};

struct Pose2 {
  double x = 0.0, y = 0.0;  // [m]
  double yaw = 0.0;         // [rad]
  bool operator==(const Pose2&) const = default;
};

inline double wrap_angle(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a < -kPi) a += 2.0 * kPi;
  return a;
}

// atan2 within 2e-5 rad (Abramowitz and Stegun 4.4.49 on [0, 1], octants folded onto it), for
// bearings looked up many times a scan, where libm's cost matters and a beam is 1e-3 rad or more
// wide. atan2(0, 0) is 0. [rad]
inline double fast_atan2(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (hi == 0.0) return 0.0;
  const double a = lo / hi, s = a * a;
  double r =
      a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))));
  if (ay > ax) r = 0.5 * kPi - r;
  if (x < 0.0) r = kPi - r;
  return y < 0.0 ? -r : r;
}

inline double clampd(double v, double lo, double hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

// A robot pose with its rotation worked out once, for moving many points between the frames
// (a loop over a scan's points calling to_world() would pay a sincos per point).
struct PoseFrame {
  explicit PoseFrame(const Pose2& p) : pose(p), c(std::cos(p.yaw)), s(std::sin(p.yaw)) {}
  // Robot-frame point [m] to the world frame [m].
  Vec2 to_world(const Vec2& r) const {
    return {pose.x + c * r.x() - s * r.y(), pose.y + s * r.x() + c * r.y()};
  }
  // World-frame point [m] to the robot frame [m].
  Vec2 to_robot(const Vec2& w) const {
    const double dx = w.x() - pose.x, dy = w.y() - pose.y;
    return {c * dx + s * dy, -s * dx + c * dy};
  }
  Pose2 pose;
  double c, s;  // cos and sin of pose.yaw
};

// Robot-frame point to world frame for a robot at `p`.
inline Vec2 to_world(const Pose2& p, const Vec2& r) {
  return PoseFrame(p).to_world(r);
}

// World-frame point to the robot frame of a robot at `p`.
inline Vec2 to_robot(const Pose2& p, const Vec2& w) {
  return PoseFrame(p).to_robot(w);
}

}  // namespace carril::fw
