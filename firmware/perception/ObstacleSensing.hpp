#pragma once
// Component: obstacles from the lidar. On every new scan: check that the lidar still measures
// something (ScanHealth), and publish the scan as points in the odometry frame (ObstacleField),
// which the missions and the mission runner query.
#include <cstdint>

#include "firmware/core/FaultSink.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/SampleReader.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/health/SensorHealth.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"
#include "firmware/perception/MovingReturns.hpp"

namespace carril::fw {

struct ObstacleSensingConfig {
  bool present = true;                         // a lidar is fitted
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;  // its mount in the robot frame [m, m, rad]
  double rate_hz = 20.0;                       // scan rate [Hz]
  double reliable_range_m = 20.0;  // what the protective fields can count on it seeing [m]
  ScanHealthConfig health;
  MovingReturnsConfig moving;  // which returns are something moving

  Status validate() const;
  bool operator==(const ObstacleSensingConfig&) const = default;
  // The mount as a pose in the robot frame: the one declaration of where the 2D lidar sits, which
  // the obstacle field, the costmap and the localiser all take [m, m, rad].
  Pose2 mount() const { return {x_m, y_m, yaw_rad}; }
};

struct ObstacleSensingTelemetry {
  std::uint64_t invalid_beams = 0;   // NaN, inf, zero or out-of-limits ranges seen
  std::uint64_t moving_returns = 0;  // returns marked moving, over every scan
  double scan_valid_fraction = 1.0;  // valid beams over the health window [0..1]
};

class ObstacleSensing {
 public:
  ObstacleSensing(const ObstacleSensingConfig& cfg, const Topic<SensorFrame>& frame,
                  const Topic<OdometryMsg>& odom, Topic<ObstacleField>& out, FaultSink& faults);

  // Task: converts the newest scan if it is new.
  void run();
  ObstacleSensingTelemetry telemetry() const;

 private:
  ScanHealth health_;
  MovingReturns moving_;
  std::uint64_t moving_returns_ = 0;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  Topic<ObstacleField>& out_;
  FaultSink& faults_;
  SampleReader<hal::LaserScan> scans_;
};

}  // namespace carril::fw
