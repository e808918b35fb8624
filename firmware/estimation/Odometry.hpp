#pragma once
// Dead reckoning: integrates the body displacement of each step in the odometry frame (its origin
// is where the robot was when the firmware started). The translation comes from the wheel encoder
// angles; the heading from the IMU's gyro when it has one, else from the wheels. A slipping wheel
// (a skid-steer turning, a wet floor) turns the wheels' heading by a few degrees per turn, and
// every metre driven afterwards carries that error sideways; the gyro does not see the slip.
#include <cstdint>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

class Odometry {
 public:
  // `gyro_heading`: integrate the IMU's yaw rate for the heading (wheels only without a good
  // sample).
  explicit Odometry(const DriveKinematics& kin, bool gyro_heading = false)
      : kin_(kin), gyro_heading_(gyro_heading) {}

  // Feeds one set of encoder readings and the newest IMU sample; the first call only latches the
  // positions. A sample counts when valid, finite, newer than the last, and at most kMaxGyroGapNs
  // after it; the heading then turns by the yaw rate integrated over the samples' interval
  // (trapezoid). Otherwise this step's heading change is the wheels'.
  void update(const hal::WheelFeedbackSet& fb, const hal::ImuSample& imu = {});
  const Pose2& pose() const { return pose_; }
  // Body twist measured from wheel speeds [m/s, rad/s].
  const Twist& twist() const { return twist_; }
  // Steps whose heading came from the gyro, and from the wheels [count].
  std::uint64_t gyro_steps() const { return gyro_steps_; }
  std::uint64_t wheel_steps() const { return wheel_steps_; }

  static constexpr hal::TimeNs kMaxGyroGapNs = 100'000'000;  // longer gaps: wheels [ns]

 private:
  // This step's heading change from the gyro; false when the sample cannot give one.
  bool gyro_turn(const hal::ImuSample& imu, double& dyaw);

  const DriveKinematics& kin_;
  bool gyro_heading_;
  bool primed_ = false;
  double last_pos_[hal::kMaxWheels] = {};
  bool gyro_primed_ = false;
  hal::TimeNs last_imu_ns_ = 0;
  double last_rate_ = 0.0;
  std::uint64_t gyro_steps_ = 0, wheel_steps_ = 0;
  Pose2 pose_;
  Twist twist_;
};

}  // namespace carril::fw
