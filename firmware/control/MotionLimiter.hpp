#pragma once
// Makes any requested twist feasible: body speed and yaw-rate caps, acceleration limits per
// tick, then wheel-speed saturation by uniform scaling (which keeps the path's curvature).
#include "firmware/core/Status.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"

namespace carril::fw {

// The robot's motion limits (the wiring file fills them from the robot description).
struct MotionLimits {
  double max_speed_mps = 1.0;           // [m/s]
  double max_yaw_rate_radps = 1.5;      // [rad/s]
  double max_accel_mps2 = 1.0;          // [m/s^2]
  double max_yaw_accel_radps2 = 3.0;    // [rad/s^2]
  double max_wheel_speed_radps = 10.0;  // [rad/s]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<MotionLimits>> params();
  Status validate() const;
  bool operator==(const MotionLimits&) const = default;
};

class MotionLimiter {
 public:
  MotionLimiter(const MotionLimits& limits, const DriveKinematics& kin, double dt_s)
      : lim_(limits), kin_(kin), dt_(dt_s) {}

  // Returns the twist actually commanded and writes its wheel speeds [rad/s].
  Twist apply(const Twist& want, float* wheel_radps);
  // Forget the ramp state (after a stop the next command starts from rest).
  void reset() { last_ = {}; }
  const Twist& last() const { return last_; }

 private:
  MotionLimits lim_;
  const DriveKinematics& kin_;
  double dt_;
  Twist last_;
};

}  // namespace carril::fw
