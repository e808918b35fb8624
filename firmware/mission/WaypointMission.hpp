#pragma once
// The waypoint course (the obstacle-avoidance practice): drive to each target of a list in
// turn, lap after lap, with the VFF follower as the only guide: pulled toward the target,
// pushed away from the costmap's obstacles, no global planner. Counts the targets reached and
// skipped, the laps and the time of each lap.
//
//   WAIT --drives ready, costmap updated--> DRIVE --last target of the last lap--> DONE
//   DRIVE --target unreachable (stuck, timed out or in an obstacle)--> FAILED, or the next
//   target when on_unreachable is Skip (counted in targets_skipped; phase "skip" for a tick)
//   DRIVE phases: "drive" (VFF) <--> "bypass" (round an obstacle in the way, see below)
//
// Unreachable: no progress of stuck_progress_m toward the target for stuck_time_s ("stuck"), or
// not reached within target_timeout_s ("timeout"): fault no_path. A target on or next to a cell
// the 2D lidar sees as lethal (the robot within reach_radius_m of it would touch it):
// goal_invalid, checked when the target becomes current and at every costmap update. A lethal
// cell just ahead of the body stops the forward motion (VFF's pull is never cancelled by the
// push, so it alone would drive into an obstacle lying on the target): the robot turns in place
// when the follower turns. When it drives straight on (the pull and the push in line: VFF's
// local minimum, e.g. a post on the line to the target) the robot goes round the obstacle
// (phase "bypass"): it holds the heading square to the push, on the side the push leans to,
// until the push no longer opposes the pull and the front is clear, then VFF drives again. With
// bypass off it holds there and the stuck check ends it.
#include <cstddef>
#include <cstdint>

#include "firmware/control/VffFollower.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/mapping/CostmapView.hpp"
#include "firmware/mission/Mission.hpp"
#include "firmware/perception/ObstacleField.hpp"

namespace carril::fw {

// What an unreachable target ends in.
enum class WaypointGiveUp : std::uint8_t {
  Fault,  // the mission fails (no_path or goal_invalid), safe stop
  Skip,   // the next target; counted in targets_skipped
};

struct WaypointConfig {
  static constexpr std::size_t kMaxTargets = 32;
  static constexpr std::uint32_t kMaxLaps = 100;

  StaticVector<Vec2, kMaxTargets> targets;  // driven to in order, odometry frame [m]
  std::uint32_t laps = 1;                   // times round the list (1..kMaxLaps) [laps]
  double reach_radius_m = 0.25;             // a target is reached this close [m]
  double speed_mps = 0.4;                   // cruise speed (the follower's cruise_speed_mps) [m/s]
  VffConfig vff;                            // the follower's forces and turning
  double target_timeout_s = 60.0;           // each target reached within this [s]
  double stuck_time_s = 10.0;               // no progress for this long is stuck [s]
  double stuck_progress_m = 0.1;            // progress: this much closer than ever before [m]
  WaypointGiveUp on_unreachable = WaypointGiveUp::Fault;
  double emergency_stop_m = 0.05;  // a lethal cell this close ahead of the body stops [m]
  // With a lethal cell just ahead, a follower turning at least this fast turns in place [rad/s].
  double turn_in_place_min_radps = 0.2;
  // Blocked straight on (a local minimum of the forces): go round the obstacle along its edge
  // (BYPASS) instead of holding until stuck.
  bool bypass = true;
  double bypass_speed_mps = 0.2;  // along the edge [m/s]

  Status validate() const;
};

class WaypointMission final : public Mission {
 public:
  // holonomic: kept for the common signature; the VFF follower drives without vy either way.
  WaypointMission(const WaypointConfig& cfg, const Footprint& footprint, bool holonomic,
                  const Topic<OdometryMsg>& pose, const CostmapView& costmap);

  const char* name() const override { return "waypoints"; }
  void enter(const MissionContext& ctx) override;
  void exit() override {}
  MissionOutput update(const MissionContext& ctx) override;
  MissionState state() const override;
  const char* take_phase_change() override;
  void counters(MissionCounters& out) const override;

  enum class State : std::uint8_t { Wait, Drive, Done, Failed };
  State current() const { return state_; }
  std::size_t target_index() const { return target_; }        // the target driven to
  std::uint32_t targets_reached() const { return reached_; }  // over all laps
  std::uint32_t targets_skipped() const { return skipped_; }  // over all laps
  std::uint32_t laps_done() const { return laps_done_; }
  std::uint32_t emergency_stops() const { return emergency_stops_; }
  std::uint32_t bypasses() const { return bypasses_; }  // times the robot went round an obstacle
  // Time of each finished lap, in order [s].
  const StaticVector<double, WaypointConfig::kMaxLaps>& lap_times() const { return lap_times_; }
  bool holonomic() const { return holonomic_; }
  const VffFollower& follower() const { return vff_; }

 private:
  void go(State s, const char* phase);
  MissionOutput drive(const MissionContext& ctx, const Pose2& pose);
  MissionOutput unreachable(const MissionContext& ctx, const Pose2& pose, Fault f,
                            const char* phase);
  MissionOutput next_target(const MissionContext& ctx, const Pose2& pose);
  void begin_target(const MissionContext& ctx, const Pose2& pose);
  bool target_in_obstacle() const;
  bool lethal_ahead(const Pose2& pose) const;
  MissionOutput bypass_step(const Pose2& pose, bool blocked) const;
  MissionOutput fail(Fault f, const char* phase);

  WaypointConfig cfg_;
  Footprint footprint_;
  bool holonomic_;
  VffFollower vff_;
  const Topic<OdometryMsg>& pose_;
  const CostmapView& costmap_;

  State state_ = State::Wait;
  const char* phase_ = "wait";
  const char* phase_change_ = nullptr;
  std::size_t target_ = 0;
  std::uint32_t reached_ = 0, skipped_ = 0, laps_done_ = 0, emergency_stops_ = 0;
  StaticVector<double, WaypointConfig::kMaxLaps> lap_times_;
  double lap_t0_ = 0.0;      // this lap began [s]
  double target_t0_ = 0.0;   // this target became current [s]
  double best_dist_ = 0.0;   // closest to the target so far [m]
  double progress_t_ = 0.0;  // last progress toward it [s]
  std::uint32_t seen_updates_ = 0;
  bool check_target_ = false;  // the current target not yet checked against the lidar layer
  bool stopped_ = false;
  bool bypass_ = false;         // going round an obstacle
  int side_ = 1;                // round it on the left (+1) or the right (-1)
  std::uint32_t bypasses_ = 0;  // held by the emergency stop last tick
  Fault fault_ = Fault::None;
};

const char* waypoint_state_name(WaypointMission::State s);

}  // namespace carril::fw
