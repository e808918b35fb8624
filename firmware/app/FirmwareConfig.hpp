#pragma once
// Everything the firmware is configured with, fixed at init. Plain data: the target's wiring
// file fills it (the simulator from the scenario and robot preset).
#include <cstdint>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"

namespace carril::fw {

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};

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

  struct Mission {
    Rgb8 line_color{255, 255, 255};
    Rgb8 end_color{255, 255, 0};
    double speed_mps = 0.5;    // cruise speed [m/s]
    int color_tolerance = 70;  // max per-channel difference to count as the colour [0..255]
  } mission;

  struct Follower {
    double lookahead_m = 0.0;  // pursuit distance from the robot centre; 0 = near edge of view [m]
    double curvature_slowdown_m = 0.6;   // v = cruise / (1 + this * |curvature|)
    double search_yaw_rate_radps = 0.6;  // turn rate while looking for a lost line [rad/s]
    double search_max_turn_rad = 6.6;    // give up (fault) after turning this far [rad]
    double end_approach_gain = 1.2;      // speed per metre to the end mark [1/s]
    double end_tolerance_m = 0.01;       // stop this close to the mark [m]
    double init_timeout_s = 3.0;         // drives and sensors must be up by then [s]
  } follower;

  double protective_stop_m = 0.30;  // stop if an obstacle is this close ahead of the bumper [m]
};

}  // namespace carril::fw
