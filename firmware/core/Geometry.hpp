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

// Robot-frame point to world frame for a robot at `p`.
inline Vec2 to_world(const Pose2& p, const Vec2& r) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return {p.x + c * r.x() - s * r.y(), p.y + s * r.x() + c * r.y()};
}

// World-frame point to the robot frame of a robot at `p`.
inline Vec2 to_robot(const Pose2& p, const Vec2& w) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  const double dx = w.x() - p.x, dy = w.y() - p.y;
  return {c * dx + s * dy, -s * dx + c * dy};
}

}  // namespace carril::fw
