#pragma once
// Everything the firmware is configured with, fixed at init. Plain data: the target's wiring
// file fills it (the simulator from the scenario and robot preset).
#include <cstdint>

#include "firmware/behavior/MissionBehavior.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/health/SensorHealth.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "firmware/perception/LineDetector.hpp"

namespace carril::fw {

struct FirmwareConfig {
  double rate_hz = 100.0;  // tick rate [Hz]
  DriveGeometry drive;
  double footprint_length_m = 0.5, footprint_width_m = 0.5;  // [m]

  MotionLimits limits;

  CameraMount camera;
  double camera_timeout_s = 0.5;  // no new frame for this long is a fault [s]
  double camera_rate_hz = 30.0;   // frame rate [Hz]

  struct Lidar {
    bool present = true;
    double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;  // mount in the robot frame
    double timeout_s = 1.0;                      // no new scan for this long is a fault [s]
    double rate_hz = 20.0;                       // scan rate [Hz]
  } lidar;

  bool imu_present = true;  // an IMU is fitted: its samples are checked (health.imu)

  // Sensor health rules (firmware/health): a sensor that publishes on time but says nothing.
  // health_config() below fills the windows from the sensor rates.
  struct Health {
    ScanHealthConfig scan;
    FrameHealthConfig frame;
    ImuHealthConfig imu;
  } health;

  LineDetectorConfig detector;  // HSV thresholds for the tape and end-mark colours
  StrategyConfig strategy;      // which follower, its gains and the cruise speed
  BehaviorConfig behavior;      // state machine and obstacle avoidance parameters
  double tape_preview_m =
      0.6;  // how far ahead along the remembered tape corners are looked for [m]
};

// The health windows for these sensor rates and limits: a blind lidar within 0.25 s of scans,
// six frames (0.2 s at 30 Hz) of one colour, an IMU yaw rate four times the robot's limit.
inline FirmwareConfig::Health health_config(const FirmwareConfig& c) {
  FirmwareConfig::Health h = c.health;
  const int scans = static_cast<int>(c.lidar.rate_hz * 0.25 + 0.5);
  h.scan.window_scans =
      scans < 2 ? 2 : (scans > ScanHealth::kMaxWindow ? ScanHealth::kMaxWindow : scans);
  const int frames = static_cast<int>(c.camera_rate_hz * 0.2 + 0.5);
  h.frame.blank_frames = frames < 2 ? 2 : frames;
  h.imu.max_yaw_rate_radps = 4.0 * c.limits.max_yaw_rate_radps;
  return h;
}

}  // namespace carril::fw
