#pragma once
// Component: runs the active mission. Every tick it hands the mission its context, raises the
// mission's faults, stops a guarded motion short of an obstacle ahead (whatever the mission
// wanted), and once any fault has latched keeps the mission stopped: the safe stop is the
// runner's, not each mission's.
#include <cstdint>

#include "firmware/core/FaultSink.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mission/LostExplorer.hpp"
#include "firmware/mission/Mission.hpp"
#include "firmware/mission/MotionCheck.hpp"
#include "firmware/mission/ObstacleGuard.hpp"
#include "firmware/mission/SafetyFields.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct MissionRunnerConfig {
  ObstacleStopConfig obstacle;
  // The protective and warning fields every motion request passes through, whatever the mission.
  SafetyFieldsConfig fields;
  // The swept-footprint check of every motion (turns in place, arcs, strafes) on the costmap.
  MotionCheckConfig check;
  // A motion the fields or the motion checks keep stopped this long in a row gives up with the
  // fault motion_blocked (the robot waits that long for a person to step aside) [s].
  double blocked_timeout_s = 30.0;
  // An active mission whose robot has not moved stall_progress_m from where it was this long,
  // while it is not deliberately waiting (held stopped by the fields, unlocalised, or a mission
  // state that waits), gives up with the fault stalled: a robot turning on the spot at a fork
  // for ever is a fault an operator sees. 0: never [s].
  double stall_timeout_s = 60.0;
  double stall_progress_m = 0.3;  // [m]
  // While the pose is not localised the mission is held; the robot then turns in place at this
  // rate, so that a 2D lidar that sees only ahead shows the localisation the whole room, or
  // stands still at 0 [rad/s]. It turns only with room to turn (see lost_turn_clearance_m).
  double lost_turn_radps = 0.0;
  // Turning in place sweeps the footprint's circumscribed circle: it turns only while every
  // lidar point, seen now or remembered from before it left the lidar's view, is at least this
  // far beyond that circle (where the lidar has never looked, it trusts the room) [m].
  double lost_turn_clearance_m = 0.05;
  // Held unlocalised this long in a row (never localised since the start, or lost since), the
  // robot gives up with the fault not_localised: a safe stop an operator sees, not a wait with
  // no end. 0: it waits for ever [s].
  double max_unlocalised_s = 0.0;
  // Still lost after a whole turn, it drives short legs toward open space and looks round again
  // from there (speed 0: it only turns). Only with a lost turn.
  LostExploreConfig lost_explore;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<MissionRunnerConfig>> params();
  Status validate() const;
  // How far beyond the footprint's circumscribed circle a return can still hold the lost turn,
  // plus 0.1 m for the travel between scans: what the obstacle field has to remember of its
  // blind sector (0 without a lost turn) [m].
  double lost_turn_reach_m(const Footprint& fp) const;
  bool operator==(const MissionRunnerConfig&) const = default;
};

struct MissionRunnerTelemetry {
  std::uint64_t obstacle_stops = 0;      // guarded motions the runner stopped for an obstacle
  std::uint64_t unlocalised_ticks = 0;   // ticks the mission was held: pose not localised
  std::uint64_t lost_turn_ticks = 0;     // of those, ticks turning in place to look round
  std::uint64_t lost_drive_ticks = 0;    // of those, ticks driving a leg toward open space
  std::uint32_t lost_legs = 0;           // legs started toward open space (LostExplorer)
  std::uint32_t lost_backs = 0;          // legs backed along for room to turn (LostExplorer)
  std::uint32_t relocalisations = 0;     // pose jumps passed on to the mission
  std::uint64_t field_stops = 0;         // ticks the protective field stopped a motion
  std::uint64_t field_slowdowns = 0;     // ticks the fields cut a motion's speed
  std::uint64_t blind_ticks = 0;         // of those, ticks driving where the lidar does not see
  std::uint64_t check_stops = 0;         // ticks a motion's swept footprint was not clear
  std::uint64_t check_slowdowns = 0;     // ticks it was cut to a speed whose stop fits
  std::uint64_t check_alternatives = 0;  // ticks the nearest clear motion replaced the request
  double blocked_max_s = 0.0;            // the longest a motion was kept stopped [s]
  // The last motion stopped, and by what: "field" (a return in the protective field), "turn"
  // (a turn on the spot's swept circle not clear), "path" (an arc's or a strafe's), "crowded".
  const char* last_stop = "";
  Twist last_stopped;
  bool stopped = false;  // the mission was stopped by a fault (safe stop)
};

class MissionRunner final : public MissionStateSource {
 public:
  MissionRunner(const MissionRunnerConfig& cfg, double period_s, int wheel_count, Mission& mission,
                const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
                const Topic<ObstacleField>& obstacles, Topic<MotionRequest>& out, FaultSink& faults,
                bool imu_present = false);

  // The pose the mission drives by (the map-frame pose): while it is not localised the runner
  // holds the robot still and does not update the mission (it would drive by a wrong pose).
  void watch_pose(const Topic<OdometryMsg>& pose) { pose_ = &pose; }
  // The costmap every motion is checked on (in the pose's frame); no view on it: the lidar alone.
  void watch_costmap(const Topic<CostmapMsg>& c) { check_.watch_costmap(c); }

  // Task: one mission update (or the safe stop).
  void run();
  const Mission& mission() const { return mission_; }
  MissionState state() const override { return mission_.state(); }
  const char* take_phase_change() override { return mission_.take_phase_change(); }
  const MissionRunnerTelemetry& telemetry() const { return tel_; }

 private:
  double period_s_;
  int wheel_count_;
  Mission& mission_;
  const Topic<SensorFrame>& frame_;
  Topic<MotionRequest>& out_;
  FaultSink& faults_;
  ObstacleGuard guard_;
  const Topic<ObstacleField>& obstacles_;
  const Topic<OdometryMsg>& odom_;
  double lost_turn_radps_, lost_turn_clearance_m_;
  double max_unlocalised_s_;
  double unlocalised_s_ = 0.0;  // held unlocalised in a row [s]
  const Topic<OdometryMsg>* pose_ = nullptr;
  std::uint32_t seen_relocalisations_ = 0;
  LostExplorer explorer_;
  MotionRequest held();
  // The request through the protective fields (cut or stopped); `stopped` when it was stopped.
  MotionRequest safeguarded(const MotionRequest& want, bool& stopped);
  // The request through the swept-footprint check (cut, or stopped: `stopped`).
  MotionRequest checked(const MotionRequest& want, bool& stopped);
  // Counts a stopped motion; false (fault raised) when it has been stopped too long.
  bool blocked_for(bool stopped);
  // Counts time without progress; false (fault raised) when the mission has stalled.
  bool progressing(bool waiting, const char* state);
  bool entered_ = false;
  bool imu_present_;
  bool imu_seen_ = false;
  MissionRunnerTelemetry tel_;
  SafetyFields fields_;
  MotionCheck check_;
  double blocked_timeout_s_, stall_timeout_s_, stall_progress_m_;
  double blocked_s_ = 0.0;
  double stall_s_ = 0.0;
  Vec2 stall_anchor_ = Vec2::Zero();
  bool anchored_ = false;
};

}  // namespace carril::fw
