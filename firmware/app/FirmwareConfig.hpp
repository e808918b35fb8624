#pragma once
// Everything the line-following firmware is configured with, fixed at init: the robot's
// description (rates, geometry, limits, sensor mounts) and each component's own config struct.
// The loader (loader/) fills it from config/robots/*.yaml and the mission file; validate() checks
// every field, and its error names the field, the value, its unit and the range.
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/estimation/Localisation.hpp"
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

namespace carril::fw {

enum class MissionKind : std::uint8_t { FollowLine, Goto, Waypoints, Coverage };

// Each task's compute budget: a run over it is an overrun, counted and reported as a throttled
// event (TaskTable). The same on both targets: Firmware::declare_tasks() is the one task table.
// [us]
struct TaskBudgets {
  double health_us = 20.0;
  double odometry_us = 20.0;
  double localisation_us = 250.0;
  double perception_us = 400.0;
  double obstacles_us = 60.0;
  double mapping_us = 400.0;
  double mission_us = 300.0;  // goto's and coverage's plans are spread over ticks within it
  double motion_us = 20.0;
  double telemetry_us = 50.0;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<TaskBudgets>> params();
  Status validate() const;
  bool operator==(const TaskBudgets&) const = default;
};

struct FirmwareConfig {
  double rate_hz = 100.0;  // control tick [Hz]
  DriveGeometry drive;
  double footprint_length_m = 0.5, footprint_width_m = 0.5;  // body outline [m]
  MotionLimits limits;
  // The odometry's heading from the IMU's yaw rate (wheels only while no good sample comes);
  // needs watch.imu_present.
  bool gyro_heading = true;

  LinePerceptionConfig camera;  // camera mount and rate, tape colours, frame health
  ObstacleSensingConfig lidar;  // lidar mount and rate, scan health
  SensorWatchConfig watch;      // device timeouts, IMU health
  MissionRunnerConfig runner;   // the obstacle stop
  MissionKind mission = MissionKind::FollowLine;  // which mission runs
  FollowLineConfig follow_line;                   // follow_line: strategy and state machine
  GotoConfig goto_mission;                        // goto: goal, planner and follower
  CoverageConfig coverage;          // coverage: the cleaning mission on the static map
  WaypointConfig waypoints;         // waypoints: the course's targets, followed with VFF
  MappingConfig mapping;            // the costmap (goto plans on it, follow_line avoids with it)
  LocalisationConfig localisation;  // on a known map: where the robot starts, how it localises
  TaskBudgets tasks;                // the task table's budgets
  // The static map (the building), owned by the target's wiring file, which keeps it alive as
  // long as the firmware; nullptr without one. Set: the costmap and the missions work in its
  // frame, and localisation.enabled must be set.
  const OccupancyGrid* map = nullptr;

  // The robot-level settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<FirmwareConfig>> params();
  Status validate() const;
  // Member by member (map: the same grid object). Two targets configured alike from the same
  // files compare equal (tests/scenario/ConfiguredAlikeTest).
  bool operator==(const FirmwareConfig&) const = default;
  Footprint footprint() const { return {0.5 * footprint_length_m, 0.5 * footprint_width_m}; }
};

// The robot can stop for what its lidar sees at its top speed: the protective field fits in
// runner.fields.max_field_m (when set), and the warning field's far corners lie within the
// lidar's reliable range. Part of validate().
Status check_stopping_reach(const FirmwareConfig& c);

// Sets what follows from the sensor rates and the robot's limits: three missed frames or five
// missed scans are a dead device (at least 0.2 s and 0.5 s); a blind lidar within 0.25 s of
// scans; six frames (0.2 s at 30 Hz) of one colour; an IMU yaw rate four times the robot's limit.
void apply_sensor_rates(FirmwareConfig& c);

}  // namespace carril::fw
