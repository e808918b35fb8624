#pragma once
// Component: watches that every device keeps talking. A drive that reports Fault, a camera or
// lidar that stops publishing, and an IMU whose samples are implausible or frozen each raise
// their fault. (What a frame or scan says is checked by the component that reads it.)
#include <cstdint>

#include "firmware/core/FaultSink.hpp"
#include "firmware/core/SampleReader.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/health/SensorHealth.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct SensorWatchConfig {
  double camera_timeout_s = 0.5;   // no new camera frame for this long is a fault [s]
  double scanner_timeout_s = 1.0;  // no new scan for this long is a fault [s]
  bool imu_present = true;         // an IMU is fitted: its samples are checked
  double imu_timeout_s = 0.2;      // no valid IMU sample for this long is a fault [s]
  ImuHealthConfig imu;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<SensorWatchConfig>> params();
  Status validate() const;
  bool operator==(const SensorWatchConfig&) const = default;
};

struct SensorWatchTelemetry {
  std::uint64_t camera_frames = 0;  // new frames seen
  std::uint64_t scans = 0;          // new scans seen
  std::uint64_t imu_samples = 0;    // valid IMU samples seen
};

class SensorWatch {
 public:
  // lidar_present: a lidar is fitted, so its silence is a fault.
  SensorWatch(const SensorWatchConfig& cfg, bool lidar_present, const Topic<SensorFrame>& frame,
              const Topic<OdometryMsg>& odom, FaultSink& faults);

  // Task: one look at every device.
  void run();
  const SensorWatchTelemetry& telemetry() const { return tel_; }

 private:
  SensorWatchConfig cfg_;
  bool lidar_present_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  FaultSink& faults_;
  ImuHealth imu_health_;
  SampleReader<hal::CameraFrame> frames_;
  SampleReader<hal::LaserScan> scans_;
  hal::TimeNs last_frame_ns_ = 0, last_scan_ns_ = 0;
  bool imu_seen_ = false;
  hal::TimeNs last_imu_ns_ = 0;
  SensorWatchTelemetry tel_;
};

}  // namespace carril::fw
