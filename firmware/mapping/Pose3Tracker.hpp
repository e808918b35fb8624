#pragma once
// The robot's 3D pose for mapping, from 2D odometry and the IMU's attitude: x, y and yaw come from
// odometry (the horizontal projection of the motion), roll and pitch from the IMU, and z is
// integrated as dz = ds * sin(pitch) over the distance travelled each tick.
//
// Attitude conventions (those of hal::ImuSample as the simulator fills it): pitch positive = nose
// UP, roll positive = left side up (right-handed about x forward); yaw counter-clockwise.
// The body rotation is R = Rz(yaw) * Ry(-pitch) * Rx(roll) (Ry(-pitch) because a right-handed
// rotation about y (left) puts the nose down).
#include <Eigen/Core>

#include "firmware/core/Geometry.hpp"

namespace carril::fw {

struct Pose3 {
  double x = 0.0, y = 0.0, z = 0.0;  // odometry frame [m]
  double roll = 0.0;                 // left side up positive [rad]
  double pitch = 0.0;                // nose up positive [rad]
  double yaw = 0.0;                  // counter-clockwise [rad]
};

// Where a sensor sits on the robot: offset from the robot's reference point (x fwd, y left, z up
// above the ground) [m] and its mounting attitude [rad] (same conventions as Pose3).
struct SensorMount {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  bool operator==(const SensorMount&) const = default;
};

// Rotation of a body with this attitude, body frame to odometry frame [rad].
Mat3 rotation_of(double roll_rad, double pitch_rad, double yaw_rad);
// Attitude (roll, pitch, yaw) [rad] of a rotation matrix, inverse of rotation_of.
void attitude_of(const Mat3& r, double& roll_rad, double& pitch_rad, double& yaw_rad);

// The pose of a sensor mounted on a robot at `body`.
Pose3 sensor_pose_of(const Pose3& body, const SensorMount& mount);

class Pose3Tracker {
 public:
  // Starts at the odometry pose `odom` with height z_m [m]; attitude zero.
  void reset(const Pose2& odom, double z_m = 0.0);
  // One tick: the new odometry pose and the IMU's roll and pitch [rad]. Non-finite attitude is
  // ignored (the last good value is kept); z follows the signed distance along the heading.
  void update(const Pose2& odom, float roll_rad, float pitch_rad);
  // The robot's 3D pose (reference point on the ground under its centre).
  const Pose3& pose() const { return pose_; }
  // The pose of a sensor mounted on the robot.
  Pose3 sensor_pose(const SensorMount& mount) const;

 private:
  Pose3 pose_;
  bool started_ = false;
};

}  // namespace carril::fw
