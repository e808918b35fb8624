#include "firmware/mapping/Pose3Tracker.hpp"

#include <cmath>

namespace carril::fw {

Mat3 rotation_of(double roll_rad, double pitch_rad, double yaw_rad) {
  const double cr = std::cos(roll_rad), sr = std::sin(roll_rad);
  // Ry(-pitch): nose up positive.
  const double cp = std::cos(pitch_rad), sp = -std::sin(pitch_rad);
  const double cy = std::cos(yaw_rad), sy = std::sin(yaw_rad);
  Mat3 r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

void attitude_of(const Mat3& r, double& roll_rad, double& pitch_rad, double& yaw_rad) {
  const double s = clampd(-r(2, 0), -1.0, 1.0);  // sin of the right-handed pitch
  pitch_rad = -std::asin(s);
  roll_rad = std::atan2(r(2, 1), r(2, 2));
  yaw_rad = std::atan2(r(1, 0), r(0, 0));
}

void Pose3Tracker::reset(const Pose2& odom, double z_m) {
  pose_ = Pose3{odom.x, odom.y, z_m, 0.0, 0.0, odom.yaw};
  started_ = true;
}

void Pose3Tracker::update(const Pose2& odom, float roll_rad, float pitch_rad) {
  if (!started_) reset(odom);
  const double new_pitch = std::isfinite(pitch_rad) ? double(pitch_rad) : pose_.pitch;
  const double new_roll = std::isfinite(roll_rad) ? double(roll_rad) : pose_.roll;
  const double dx = odom.x - pose_.x, dy = odom.y - pose_.y;
  if (std::isfinite(dx) && std::isfinite(dy)) {
    // Signed horizontal distance along the heading (reversing down a ramp lowers z). Odometry is
    // the horizontal projection, so the slope distance is ds / cos(pitch) and
    // dz = ds * tan(pitch); the mean pitch over the tick keeps a ramp's start and end exact.
    const double heading = 0.5 * (pose_.yaw + odom.yaw);
    const double ds = dx * std::cos(heading) + dy * std::sin(heading);
    const double mean_pitch = 0.5 * (pose_.pitch + new_pitch);
    pose_.z += ds * std::tan(mean_pitch);
    pose_.x = odom.x;
    pose_.y = odom.y;
  }
  if (std::isfinite(odom.yaw)) pose_.yaw = odom.yaw;
  pose_.pitch = new_pitch;
  pose_.roll = new_roll;
}

Pose3 Pose3Tracker::sensor_pose(const SensorMount& m) const {
  return sensor_pose_of(pose_, m);
}

Pose3 sensor_pose_of(const Pose3& body_pose, const SensorMount& m) {
  const Pose3& pose_ = body_pose;
  const Mat3 body = rotation_of(pose_.roll, pose_.pitch, pose_.yaw);
  const Vec3 t = Vec3(pose_.x, pose_.y, pose_.z) + body * Vec3(m.x_m, m.y_m, m.z_m);
  const Mat3 r = body * rotation_of(m.roll_rad, m.pitch_rad, m.yaw_rad);
  Pose3 s;
  s.x = t.x();
  s.y = t.y();
  s.z = t.z();
  attitude_of(r, s.roll, s.pitch, s.yaw);
  return s;
}

}  // namespace carril::fw
