#pragma once
// Pinhole camera looking forward along the robot's x axis, tilted down, over a flat floor.
// Maps floor points in the robot frame (x forward, y left, z = 0 on the floor) to pixels and
// back through a homography built from the mounting and intrinsics. Pixel centres are at
// integer coordinates (OpenCV's convention); u to the right, v down.
#include <Eigen/Core>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct CameraMount {
  double x_m = 0.0, y_m = 0.0, z_m = 0.5;  // optical centre in the robot frame [m]
  double tilt_rad = 0.8;                   // optical axis below horizontal [rad]
  double hfov_rad = 1.0;                   // horizontal field of view [rad]
  int width = 640, height = 480;           // [px]

  Status validate() const;
  bool operator==(const CameraMount&) const = default;
};

class CameraModel {
 public:
  explicit CameraModel(const CameraMount& m);

  const CameraMount& mount() const { return m_; }
  double fx() const { return f_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }

  // Robot-frame 3D point to pixel; false when the point is not in front of the camera.
  bool project(const Vec3& p_robot, Vec2& px) const;
  // Floor point (robot frame) to pixel through the homography; false behind the camera.
  bool floor_to_pixel(const Vec2& floor, Vec2& px) const;
  // Pixel to floor point (robot frame); false when the pixel's ray does not hit the floor.
  bool pixel_to_floor(const Vec2& px, Vec2& floor) const;
  // Robot-frame point to camera frame (x right, y down, z along the optical axis).
  Vec3 to_camera(const Vec3& p_robot) const;

 private:
  CameraMount m_;
  double f_, cx_, cy_;
  Mat3 rot_;     // rows: camera axes expressed in the robot frame
  Vec3 centre_;  // optical centre, robot frame
  Mat3 h_;       // floor (x, y, 1) -> image (u, v, 1)
  Mat3 h_inv_;   // image -> floor
};

}  // namespace carril::fw
