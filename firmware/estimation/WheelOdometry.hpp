#pragma once
// Component: dead reckoning from the wheel encoders (and the gyro's heading, `gyro_heading`).
// Reads the sensor frame, publishes the odometry pose and the measured body twist every tick.
#include <cstdint>

#include "firmware/core/Topic.hpp"
#include "firmware/estimation/Odometry.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct WheelOdometryTelemetry {
  std::uint64_t updates = 0;      // encoder readings integrated
  double distance_m = 0.0;        // path length driven, from the encoders [m]
  std::uint64_t gyro_steps = 0;   // steps whose heading change came from the gyro [count]
  std::uint64_t wheel_steps = 0;  // ... and from the wheels [count]
};

class WheelOdometry {
 public:
  WheelOdometry(const DriveKinematics& kin, const Topic<SensorFrame>& frame,
                Topic<OdometryMsg>& out, bool gyro_heading = false)
      : odom_(kin, gyro_heading), frame_(frame), out_(out) {}

  // Task: one encoder reading in, one odometry message out.
  void run();
  const WheelOdometryTelemetry& telemetry() const { return tel_; }

 private:
  Odometry odom_;
  const Topic<SensorFrame>& frame_;
  Topic<OdometryMsg>& out_;
  WheelOdometryTelemetry tel_;
};

}  // namespace carril::fw
