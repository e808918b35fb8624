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
// Unreachable: no progress of stuck_progress_m toward the target for stuck_time_s ("stuck"; while
// going round an obstacle, moving stuck_progress_m along its edge counts as progress, but coming
// back to where the bypass began is "stuck" at once), or not reached within target_timeout_s
// ("timeout"): fault no_path. A target on or next to a cell the 2D lidar sees as lethal (the
// robot within reach_radius_m of it would touch it): goal_invalid, checked when the target
// becomes current and at every costmap update.
//
// Every twist, VFF's or the bypass's, passes the body guard (BodyGuard: the costmap's lethal
// cells against the rectangular body padded by body_pad_m, corners included). The forward speed
// is cut to what stops, within reaction_s and at brake_decel_mps2, emergency_stop_m short of the
// first cell on the arc driven. Stopped, the robot turns in place only when the turn clears the
// corners; when it does not, it moves straight, ahead or back (up to 1 m), to the nearest place
// from which it does ("escapes"), or holds.
//
// VFF's pull is never cancelled by its push, so alone it would drive into an obstacle on the line
// to the target. A lethal cell in the body's corridor toward the target (within the padded half
// width of the line) nearer than the bypass distance plus 0.1 m, or the guard holding a straight
// drive, starts a bypass (phase "bypass"): the robot follows the obstacle's edge with its centre
// at the bypass distance (the padded body's swept circle plus bypass_clearance_m: it can always
// turn in place there), on the side where the obstacle leaves more of the corridor (VFF's push
// decides a tie). An obstacle met straight ahead while following joins the edge (a gap too narrow
// to follow through is gone round outside). The bypass ends when the corridor to the target, 5 cm
// wider, is clear for 0.8 m and the robot is closer to the target than it ever was before the
// bypass (as in Bug2: no drive-bypass cycle repeats), or when the edge is lost. A target at an
// obstacle (within the bypass distance of it) is not gone round: the guard holds the robot short
// and the stuck check ends it. With bypass off the robot holds there too.
#include <cstddef>
#include <cstdint>

#include "firmware/control/VffFollower.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/BodyGuard.hpp"
#include "firmware/mission/Mission.hpp"
#include "firmware/mission/MissionPhase.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"

namespace carril::fw {

// VFF as the course drives it: pushed by the lethal cells only, not by the inflated band round
// them (the body guard and the bypass keep the clearance). Pushed by the band as well, two
// obstacles either side of a gap fill the push's cap with a push square against the pull, and
// the heading swings to and fro in front of a gap 1.5 m wide.
inline VffConfig course_vff() {
  VffConfig v;
  v.cost_threshold = cost::kLethal;
  return v;
}

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
  VffConfig vff = course_vff();             // the follower's forces and turning
  double target_timeout_s = 60.0;           // each target reached within this [s]
  double stuck_time_s = 10.0;               // no progress for this long is stuck [s]
  double stuck_progress_m = 0.1;            // progress: this much closer than ever before [m]
  WaypointGiveUp on_unreachable = WaypointGiveUp::Fault;
  double emergency_stop_m = 0.05;  // stops this far short of a lethal cell (padded body) [m]
  double body_pad_m = 0.05;        // kept round the body in every collision check [m]
  double reaction_s = 0.2;         // command to braking, and the costmap's staleness [s]
  double brake_decel_mps2 = 0.5;   // deceleration the stopping distance assumes [m/s^2]
  double escape_speed_mps = 0.1;   // moving to where a blocked turn is clear [m/s]
  // A blocked robot turns in place only when the follower turns at least this fast [rad/s].
  double turn_in_place_min_radps = 0.2;
  // Go round an obstacle on the line to the target (BYPASS) instead of holding until stuck.
  bool bypass = true;
  double bypass_speed_mps = 0.2;  // along the edge [m/s]
  // BYPASS keeps the centre this much beyond the padded body's swept circle from the edge [m].
  double bypass_clearance_m = 0.05;

  Status validate() const;
  bool operator==(const WaypointConfig&) const = default;
};

class WaypointMission final : public Mission {
 public:
  // holonomic: kept for the common signature; the VFF follower drives without vy either way.
  WaypointMission(const WaypointConfig& cfg, const Footprint& footprint, bool holonomic,
                  const Topic<OdometryMsg>& pose, const Topic<CostmapMsg>& costmap);

  const char* name() const override { return "waypoints"; }
  void enter(const MissionContext& ctx) override;
  void exit() override {}
  MissionOutput update(const MissionContext& ctx) override;
  MissionState state() const override;
  const char* take_phase_change() override { return phase_.take_change(); }
  void counters(MissionCounters& out) const override;

  enum class State : std::uint8_t { Wait, Drive, Done, Failed };
  State current() const { return state_; }
  std::size_t target_index() const { return target_; }        // the target driven to
  std::uint32_t targets_reached() const { return reached_; }  // over all laps
  std::uint32_t targets_skipped() const { return skipped_; }  // over all laps
  std::uint32_t laps_done() const { return laps_done_; }
  std::uint32_t emergency_stops() const { return emergency_stops_; }
  std::uint32_t bypasses() const { return bypasses_; }  // times the robot went round an obstacle
  // Times it moved straight, ahead or back, to where a blocked turn was clear.
  std::uint32_t escapes() const { return escapes_; }
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
  double stop_distance(double v) const;   // reaction, braking and margin at speed v [m]
  double speed_for(double free_m) const;  // the speed that stops within free_m [m/s]
  double keep_m() const;                  // BYPASS's distance from centre to edge [m]
  // The twist the body guard lets through; blocked_straight: a straight-on drive stopped.
  Twist guarded(const Twist& want, bool& blocked_straight);
  bool in_the_way(const Pose2& pose, const Vec2& to_target, double dist) const;
  void start_bypass(const Pose2& pose, const Vec2& to_target);
  BodyGuard::Nearest follow_edge(const Pose2& pose);
  bool bypass_over(const Pose2& pose, const BodyGuard::Nearest& edge, const Vec2& to_target,
                   double dist) const;
  Twist bypass_twist(const BodyGuard::Nearest& edge) const;
  MissionOutput fail(Fault f, const char* phase);

  WaypointConfig cfg_;
  Footprint footprint_;
  bool holonomic_;
  VffFollower vff_;
  const Topic<OdometryMsg>& pose_;
  // The costmap (its view, published at init by Mapping; validate() requires one).
  CostmapInput costmap_in_;
  const CostmapView& costmap() const { return costmap_in_.get(); }

  State state_ = State::Wait;
  MissionPhase phase_;
  std::size_t target_ = 0;
  std::uint32_t reached_ = 0, skipped_ = 0, laps_done_ = 0, emergency_stops_ = 0;
  StaticVector<double, WaypointConfig::kMaxLaps> lap_times_;
  double lap_t0_ = 0.0;      // this lap began [s]
  double target_t0_ = 0.0;   // this target became current [s]
  double best_dist_ = 0.0;   // distance at the last progress toward the target [m]
  double progress_t_ = 0.0;  // last progress toward it [s]
  std::uint32_t seen_updates_ = 0;
  bool check_target_ = false;   // the current target not yet checked against the lidar layer
  bool stopped_ = false;        // held by the guard last tick
  bool bypass_ = false;         // going round an obstacle
  int side_ = 1;                // round it on the left (+1) or the right (-1)
  Vec2 progress_at_{0.0, 0.0};  // where the last progress was made [m]
  Vec2 bypass_from_{0.0, 0.0};  // where this bypass began [m]
  Vec2 edge_{0.0, 0.0};         // the point of the obstacle's edge followed [m]
  bool bypass_left_ = false;    // this bypass has been well away from where it began
  double closest_ = 0.0;        // closest to the target outside bypasses [m]
  double bypass_best_ = 0.0;    // closest_ when this bypass began [m]
  std::uint32_t bypasses_ = 0, escapes_ = 0;
  bool escaping_ = false;  // moving to where a blocked turn is clear, last tick
  BodyGuard guard_;
  Fault fault_ = Fault::None;
};

const char* waypoint_state_name(WaypointMission::State s);

}  // namespace carril::fw
