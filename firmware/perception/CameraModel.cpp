#include "firmware/perception/CameraModel.hpp"

#include <Eigen/LU>
#include <cmath>

namespace carril::fw {

CameraModel::CameraModel(const CameraMount& m)
    : m_(m),
      f_((m.width / 2.0) / std::tan(m.hfov_rad / 2.0)),
      cx_((m.width - 1) / 2.0),
      cy_((m.height - 1) / 2.0),
      centre_(m.x_m, m.y_m, m.z_m) {
  const double c = std::cos(m.tilt_rad), s = std::sin(m.tilt_rad);
  // Optical axis forward and down; image right is the robot's -y; image down completes the frame.
  rot_.row(0) = Vec3(0, -1, 0);
  rot_.row(1) = Vec3(-s, 0, -c);
  rot_.row(2) = Vec3(c, 0, -s);
  Mat3 k;
  k << f_, 0, cx_, 0, f_, cy_, 0, 0, 1;
  // For floor points (x, y, 0): p_cam = R * ([x y 0] - C) = [r1 r2 -R*C] * [x y 1].
  Mat3 rt;
  rt.col(0) = rot_.col(0);
  rt.col(1) = rot_.col(1);
  rt.col(2) = -rot_ * centre_;
  h_ = k * rt;
  h_inv_ = h_.inverse();
}

Vec3 CameraModel::to_camera(const Vec3& p_robot) const {
  return rot_ * (p_robot - centre_);
}

bool CameraModel::project(const Vec3& p_robot, Vec2& px) const {
  const Vec3 pc = to_camera(p_robot);
  if (pc.z() <= 1e-6) return false;
  px = Vec2(f_ * pc.x() / pc.z() + cx_, f_ * pc.y() / pc.z() + cy_);
  return true;
}

bool CameraModel::floor_to_pixel(const Vec2& floor, Vec2& px) const {
  const Vec3 q = h_ * Vec3(floor.x(), floor.y(), 1.0);
  if (q.z() <= 1e-9) return false;
  px = Vec2(q.x() / q.z(), q.y() / q.z());
  return true;
}

bool CameraModel::pixel_to_floor(const Vec2& px, Vec2& floor) const {
  const Vec3 q = h_inv_ * Vec3(px.x(), px.y(), 1.0);
  // The ray hits the floor in front of the camera only when the homogeneous scale is positive
  // (h_'s third row is the point's depth along the optical axis).
  if (q.z() <= 1e-9) return false;
  floor = Vec2(q.x() / q.z(), q.y() / q.z());
  return true;
}

}  // namespace carril::fw

namespace carril::fw {

Status CameraMount::validate() const {
  return Checks("camera")
      .range("x_m", x_m, -5.0, 5.0, "m")
      .range("y_m", y_m, -5.0, 5.0, "m")
      .range("z_m", z_m, 0.02, 5.0, "m")
      .range("tilt_rad", tilt_rad, 0.05, 1.5707963268, "rad")  // up to straight down
      .range("hfov_rad", hfov_rad, 0.05, 3.0, "rad")
      .range("width", width, 16, hal::kMaxImageWidth, "px")
      .range("height", height, 16, hal::kMaxImageHeight, "px")
      .result();
}

}  // namespace carril::fw
