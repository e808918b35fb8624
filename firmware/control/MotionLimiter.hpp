#pragma once
// Makes any requested twist feasible: body speed and yaw-rate caps, acceleration limits per
// tick, then wheel-speed saturation by uniform scaling (which keeps the path's curvature).
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"

namespace carril::fw {

class MotionLimiter {
 public:
  MotionLimiter(const FirmwareConfig::Limits& limits, const DriveKinematics& kin, double dt_s)
      : lim_(limits), kin_(kin), dt_(dt_s) {}

  // Returns the twist actually commanded and writes its wheel speeds [rad/s].
  Twist apply(const Twist& want, float* wheel_radps);
  // Forget the ramp state (after a stop the next command starts from rest).
  void reset() { last_ = {}; }
  const Twist& last() const { return last_; }

 private:
  FirmwareConfig::Limits lim_;
  const DriveKinematics& kin_;
  double dt_;
  Twist last_;
};

}  // namespace carril::fw
