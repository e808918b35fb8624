#pragma once
// Everything the firmware is configured with, fixed at init. Plain data: the target's wiring
// file fills it (the simulator from the scenario and robot preset).
#include <cstdint>

#include "firmware/behavior/MissionBehavior.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "firmware/perception/LineDetector.hpp"

namespace carril::fw {

struct FirmwareConfig {
  double rate_hz = 100.0;  // tick rate [Hz]
  DriveGeometry drive;
  double footprint_length_m = 0.5, footprint_width_m = 0.5;  // [m]

  struct Limits {
    double max_speed_mps = 1.0;           // [m/s]
    double max_yaw_rate_radps = 1.5;      // [rad/s]
    double max_accel_mps2 = 1.0;          // [m/s^2]
    double max_yaw_accel_radps2 = 3.0;    // [rad/s^2]
    double max_wheel_speed_radps = 10.0;  // [rad/s]
  } limits;

  CameraMount camera;
  double camera_timeout_s = 0.5;  // no new frame for this long is a fault [s]

  struct Lidar {
    bool present = true;
    double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;  // mount in the robot frame
    double timeout_s = 1.0;                      // no new scan for this long is a fault [s]
  } lidar;

  LineDetectorConfig detector;  // HSV thresholds for the tape and end-mark colours
  StrategyConfig strategy;      // which follower, its gains and the cruise speed
  BehaviorConfig behavior;      // state machine and obstacle avoidance parameters
  double tape_preview_m =
      0.6;  // how far ahead along the remembered tape corners are looked for [m]
};

}  // namespace carril::fw
