#pragma once
// Dead reckoning from wheel encoder angles: integrates the body displacement of each step in the
// odometry frame (its origin is where the robot was when the firmware started).
#include "firmware/kinematics/DriveKinematics.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

class Odometry {
 public:
  explicit Odometry(const DriveKinematics& kin) : kin_(kin) {}

  // Feeds one set of encoder readings; the first call only latches the positions.
  void update(const hal::WheelFeedbackSet& fb);
  const Pose2& pose() const { return pose_; }
  // Body twist measured from wheel speeds [m/s, rad/s].
  const Twist& twist() const { return twist_; }

 private:
  const DriveKinematics& kin_;
  bool primed_ = false;
  double last_pos_[hal::kMaxWheels] = {};
  Pose2 pose_;
  Twist twist_;
};

}  // namespace carril::fw
