#pragma once
// The line-following firmware: its data bus and every component, created from one validated
// FirmwareConfig and connected here in the order data flows. The target's wiring file creates
// one, declares its task table (which component runs at what rate, with what budget) and
// drives tick() from its loop.
#include <cstdint>
#include <memory>

#include "firmware/app/Bus.hpp"
#include "firmware/app/Controller.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/StatusReporter.hpp"
#include "firmware/control/MotionOutput.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/estimation/Localisation.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/health/SensorWatch.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/mapping/Mapping.hpp"
#include "firmware/mission/CoverageMission.hpp"
#include "firmware/mission/FollowLineMission.hpp"
#include "firmware/mission/GotoMission.hpp"
#include "firmware/mission/MissionRunner.hpp"
#include "firmware/mission/WaypointMission.hpp"
#include "firmware/perception/LinePerception.hpp"
#include "firmware/perception/ObstacleSensing.hpp"
#include "hal/Clock.hpp"
#include "hal/TripleBuffer.hpp"

namespace carril::fw {

// Everything the firmware reports, refreshed by the telemetry task (and by refresh_telemetry()).
struct FirmwareTelemetry {
  ControllerTelemetry controller;
  const char* mission = "";
  MissionCounters mission_counters;
  MissionRunnerTelemetry runner;
  SensorWatchTelemetry watch;
  WheelOdometryTelemetry odometry;
  MotionOutputTelemetry output;
  LinePerceptionTelemetry perception;
  ObstacleSensingTelemetry obstacles;
  MappingTelemetry mapping;
  LocalisationTelemetry localisation;
  Pose2 odom;
};

// What a target's task table derives from the configuration: sensor tasks at their sensor's rate,
// or every tick when the sensor is faster (the newest frame or scan is taken, the ones between
// skipped); scans one tick after frames (spreading the two heaviest tasks); telemetry at 10 Hz
// on the last tick of its period.
struct TaskRates {
  double control_hz = 0.0, camera_hz = 0.0, lidar_hz = 0.0;  // [Hz]
  double telemetry_hz = 10.0;                                // [Hz]
  std::uint32_t scan_offset = 0, telemetry_offset = 0;       // [ticks]
};
TaskRates task_rates(const FirmwareConfig& c);

class Firmware {
 public:
  // cfg must have passed validate() (asserted by the wiring file; see Status there).
  Firmware(const FirmwareConfig& cfg, const hal::Clock& clock);
  Firmware(const Firmware&) = delete;
  Firmware& operator=(const Firmware&) = delete;

  // The components' set-up at init: the first that failed (a configuration validate() let
  // through); the wiring refuses to run a firmware whose set-up failed.
  Status init_status() const;

  // Init only: the task table, the same on every target (the target adds only its slow rate
  // group): which component runs at what rate and offset, with FirmwareConfig::tasks' budgets.
  Status declare_tasks();

  // One control period.
  ActuatorCommand tick(const SensorFrame& frame) { return controller.tick(frame); }

  // Task: refreshes telemetry() (percentiles included: run it at a low rate) and hands a status
  // snapshot to the slow rate group (status).
  void refresh_telemetry();
  const FirmwareTelemetry& telemetry() const { return telemetry_; }
  const FirmwareConfig& config() const { return cfg_; }

  // The mission the runner runs (FirmwareConfig::mission).
  const Mission& active_mission() const;
  // A mission counter by name (0 when the mission keeps none of that name).
  std::uint32_t mission_counter(const char* name) const;

  // The map a coverage mission reads when none is configured (empty).
  static inline const OccupancyGrid no_map_{};
  const DriveKinematics kinematics;
  Bus bus;
  // The components, in the order data flows through them.
  Controller controller;  // the schedule and the fault latch (the FaultSink of the others)
  SensorWatch watch;
  WheelOdometry odometry;
  Localisation localisation;  // the pose in the map frame (odometry without a map)
  LinePerception perception;
  ObstacleSensing obstacle_sensing;
  Mapping mapping;  // the costmap (a CostmapView for the missions)
  FollowLineMission mission;
  GotoMission goto_mission;
  WaypointMission waypoints;
  // Built only for a coverage mission (its area, decomposition and tour are made at init).
  std::unique_ptr<CoverageMission> coverage;
  MissionRunner runner;  // runs the configured one of the missions above
  MotionOutput output;
  // Control loop -> slow rate group: the newest status snapshot (read by a StatusReporter).
  hal::TripleBuffer<StatusSnapshot> status;

 private:
  // The mission of that kind (members above are constructed before the runner takes one).
  Mission& select_mission(MissionKind kind);
  const FirmwareConfig cfg_;
  FirmwareTelemetry telemetry_;
};

}  // namespace carril::fw
