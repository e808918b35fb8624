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
};

inline double wrap_angle(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a < -kPi) a += 2.0 * kPi;
  return a;
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
