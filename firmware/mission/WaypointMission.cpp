#include "firmware/mission/WaypointMission.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/MissionStates.hpp"
#include "firmware/mission/WaypointBypass.hpp"

namespace carril::fw {

using namespace waypoint_bypass;

namespace {

// DRIVE's phases (compared by address).
constexpr const char* kDrive = "drive";
constexpr const char* kSkip = "skip";  // one tick: a target was given up, the next one is current

// The guard: a cut forward speed below kCreepMps is a stop (its arcs, turns and escapes:
// BodyGuard's constants).
constexpr double kCreepMps = 0.02;  // [m/s]

// The follower as the mission drives it: its cruise speed is the mission's.
VffConfig follower_config(const WaypointConfig& cfg) {
  VffConfig v = cfg.vff;
  v.cruise_speed_mps = cfg.speed_mps;
  return v;
}

}  // namespace

Status WaypointConfig::validate() const {
  Checks c("waypoints");
  c.fail_if(targets.empty(), "targets", "empty, expected 1 to 32 targets")
      .range("laps", double(laps), 1.0, double(kMaxLaps), "laps")
      .range("reach_radius_m", reach_radius_m, 0.02, 5.0, "m")
      .range("speed_mps", speed_mps, 0.01, 5.0, "m/s")
      .range("target_timeout_s", target_timeout_s, 1.0, 3600.0, "s")
      .range("stuck_time_s", stuck_time_s, 0.5, 3600.0, "s")
      .range("stuck_progress_m", stuck_progress_m, 0.01, 5.0, "m")
      .range("emergency_stop_m", emergency_stop_m, 0.0, 1.0, "m")
      .range("body_pad_m", body_pad_m, 0.0, 0.5, "m")
      .range("reaction_s", reaction_s, 0.0, 2.0, "s")
      .range("brake_decel_mps2", brake_decel_mps2, 0.05, 20.0, "m/s^2")
      .range("escape_speed_mps", escape_speed_mps, 0.01, 1.0, "m/s")
      .range("bypass_clearance_m", bypass_clearance_m, 0.0, 1.0, "m")
      .range("turn_in_place_min_radps", turn_in_place_min_radps, 0.0, 10.0, "rad/s")
      .nested(follower_config(*this).validate())
      .range("bypass_speed_mps", bypass_speed_mps, 0.01, speed_mps, "m/s");
  for (std::size_t k = 0; k < targets.size() && c.result().is_ok(); ++k) {
    const Vec2& t = targets[k];
    if (!(std::islessequal(std::fabs(t.x()), 1000.0) &&
          std::islessequal(std::fabs(t.y()), 1000.0))) {
      return Status::error("waypoints.targets[%zu]: (%g, %g) m, expected -1000 to 1000 m", k, t.x(),
                           t.y());
    }
  }
  return c.result();
}

const char* waypoint_state_name(WaypointMission::State s) {
  switch (s) {
    case WaypointMission::State::Wait:
      return "WAIT";
    case WaypointMission::State::Drive:
      return "DRIVE";
    case WaypointMission::State::Done:
      return "DONE";
    case WaypointMission::State::Failed:
      return "FAILED";
  }
  return "?";
}

WaypointMission::WaypointMission(const WaypointConfig& cfg, const Footprint& footprint,
                                 bool holonomic, const Topic<OdometryMsg>& pose,
                                 const Topic<CostmapMsg>& costmap)
    : cfg_(cfg),
      footprint_(footprint),
      holonomic_(holonomic),
      vff_(follower_config(cfg)),
      pose_(pose),
      costmap_in_(costmap),
      // Gathered: what the keeping distance and the longest stopping distance can reach.
      guard_(footprint.half_length_m, footprint.half_width_m, cfg.body_pad_m,
             footprint.circumscribed_m() + cfg.body_pad_m +
                 std::fmax(cfg.bypass_clearance_m + kEnterMarginM + kLostM,
                           cfg.speed_mps * cfg.reaction_s +
                               cfg.speed_mps * cfg.speed_mps / (2.0 * cfg.brake_decel_mps2) +
                               cfg.emergency_stop_m) +
                 0.1) {}

void WaypointMission::go(State s, const char* phase) {
  phase_.set(phase, s != state_);
  state_ = s;
}

void WaypointMission::enter(const MissionContext&) {
  state_ = State::Wait;
  phase_.restart("wait");
  target_ = 0;
  reached_ = skipped_ = laps_done_ = emergency_stops_ = 0;
  lap_times_.clear();
  stopped_ = bypass_ = escaping_ = false;
  bypasses_ = escapes_ = 0;
  fault_ = Fault::None;
}

MissionState WaypointMission::state() const {
  const bool finishing =
      state_ == State::Drive && laps_done_ + 1 >= cfg_.laps && target_ + 1 >= cfg_.targets.size();
  return report_state(state_, waypoint_state_name(state_), phase_,
                      finishing ? MissionStatus::Finishing : MissionStatus::Active);
}

void WaypointMission::counters(MissionCounters& out) const {
  out.clear();
  out.push_back({"targets_reached", reached_});
  out.push_back({"targets_skipped", skipped_});
  out.push_back({"laps", laps_done_});
  const double last = lap_times_.empty() ? 0.0 : lap_times_.back();
  double best = lap_times_.empty() ? 0.0 : lap_times_[0];
  for (double t : lap_times_) best = std::fmin(best, t);
  out.push_back({"last_lap_ms", static_cast<std::uint32_t>(std::lround(last * 1000.0))});
  out.push_back({"best_lap_ms", static_cast<std::uint32_t>(std::lround(best * 1000.0))});
  out.push_back({"emergency_stops", emergency_stops_});
  out.push_back({"bypasses", bypasses_});
  out.push_back({"escapes", escapes_});
}

MissionOutput WaypointMission::fail(Fault f, const char* phase) {
  fault_ = f;
  go(State::Failed, phase);
  return fault_output(f);
}

MissionOutput WaypointMission::update(const MissionContext& ctx) {
  const Pose2 pose = pose_.get().pose;
  switch (state_) {
    case State::Wait:
      if (!ctx.drives_ready || costmap().updates() == 0) return {};
      if (cfg_.targets.empty()) {
        go(State::Done, "done");
        return {};
      }
      // The emergency stop reads the master: without one the robot would drive blind.
      if (!costmap().master().ready()) return fail(Fault::NoPath, "no_costmap");
      lap_t0_ = ctx.t_s;
      go(State::Drive, kDrive);
      begin_target(ctx, pose);
      return drive(ctx, pose);
    case State::Drive:
      return drive(ctx, pose);
    case State::Done:
      return {};
    case State::Failed: {
      MissionOutput out;
      out.fault = fault_;
      return out;
    }
  }
  return {};
}

void WaypointMission::begin_target(const MissionContext& ctx, const Pose2& pose) {
  vff_.reset();
  target_t0_ = progress_t_ = ctx.t_s;
  progress_at_ = Vec2(pose.x, pose.y);
  best_dist_ = closest_ = (cfg_.targets[target_] - progress_at_).norm();
  check_target_ = true;
  stopped_ = escaping_ = false;
  bypass_ = false;
}

// Target reached or skipped: the next one, the next lap, or DONE.
MissionOutput WaypointMission::next_target(const MissionContext& ctx, const Pose2& pose) {
  if (++target_ >= cfg_.targets.size()) {
    lap_times_.push_back(ctx.t_s - lap_t0_);
    ++laps_done_;
    if (laps_done_ >= cfg_.laps) {
      go(State::Done, "done");
      return {};
    }
    target_ = 0;
    lap_t0_ = ctx.t_s;
  }
  begin_target(ctx, pose);
  return {};  // the next target is checked and driven to from the next tick
}

MissionOutput WaypointMission::unreachable(const MissionContext& ctx, const Pose2& pose, Fault f,
                                           const char* phase) {
  if (cfg_.on_unreachable == WaypointGiveUp::Fault) return fail(f, phase);
  ++skipped_;
  const MissionOutput out = next_target(ctx, pose);
  if (state_ == State::Drive) go(State::Drive, kSkip);
  return out;
}

// A lethal cell the 2D lidar has seen, closer to the target than the circumscribed radius less
// the reach radius (the target's own cell always counts): the robot cannot come within
// reach_radius_m of the target without touching it.
bool WaypointMission::target_in_obstacle() const {
  const Vec2& t = cfg_.targets[target_];
  const double circumscribed = footprint_.circumscribed_m();
  const double radius = std::fmax(0.0, circumscribed - cfg_.reach_radius_m);
  // The lidar's returns, and on a map its walls, whether seen yet or not.
  for (const RollingGrid<std::uint8_t>* o : {&costmap().obstacles(), costmap().walls()}) {
    if (o == nullptr || !o->ready()) continue;
    int tx = 0, ty = 0;
    if (!o->world_to_cell(t.x(), t.y(), tx, ty)) continue;  // not in this window yet
    const int r = static_cast<int>(std::ceil(radius / o->resolution()));
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        if (std::hypot(dx, dy) * o->resolution() > radius && (dx != 0 || dy != 0)) continue;
        if (o->contains(tx + dx, ty + dy) && o->at(tx + dx, ty + dy) == cost::kLethal) return true;
      }
    }
  }
  return false;
}

double WaypointMission::stop_distance(double v) const {
  return v * cfg_.reaction_s + v * v / (2.0 * cfg_.brake_decel_mps2) + cfg_.emergency_stop_m;
}

// The root of v reaction + v^2 / (2 decel) = free - emergency_stop_m.
double WaypointMission::speed_for(double free_m) const {
  const double room = free_m - cfg_.emergency_stop_m;
  if (!(room > 0.0)) return 0.0;
  const double a = cfg_.brake_decel_mps2, t = cfg_.reaction_s;
  return a * (std::sqrt(t * t + 2.0 * room / a) - t);
}

double WaypointMission::keep_m() const {
  return guard_.swept_radius() + cfg_.bypass_clearance_m;
}

Twist WaypointMission::guarded(const Twist& want, bool& blocked_straight) {
  blocked_straight = false;
  Twist t;
  bool stop = false;
  if (want.vx > 0.0) {
    // Along the arc asked for, as fast as stops short of its first cell.
    const double k = clampd(want.wz / want.vx, -BodyGuard::kMaxCurvature, BodyGuard::kMaxCurvature);
    const double reach = stop_distance(want.vx);
    const double v = std::fmin(want.vx, speed_for(guard_.free_length(k, false, reach)));
    if (v >= want.vx || v >= kCreepMps) {
      t.vx = v;
      t.wz = k * v;
      stopped_ = escaping_ = false;
      return t;
    }
    stop = true;
  }
  if (stop && !stopped_) ++emergency_stops_;
  stopped_ = stop;
  // In place: the turn asked for, or what is left of a blocked arc. Straight on: hold.
  if (std::fabs(want.wz) < cfg_.turn_in_place_min_radps) {
    blocked_straight = stop;
    escaping_ = false;
    return t;
  }
  const double horizon = std::fabs(want.wz) * cfg_.reaction_s + BodyGuard::kTurnMarginRad;
  if (guard_.rotation_clear(std::copysign(horizon, want.wz))) {
    t.wz = want.wz;
    escaping_ = false;
    return t;
  }
  // A corner would touch: move straight, ahead or back, to the nearest place within
  // BodyGuard::kEscapeM from which the turn is clear (behind first: the robot came from there).
  const double shift =
      guard_.escape_shift(std::copysign(horizon, want.wz), BodyGuard::kEscapeStepM,
                          BodyGuard::kEscapeM, stop_distance(cfg_.escape_speed_mps));
  if (shift != 0.0) {
    if (!escaping_) ++escapes_;
    escaping_ = true;
    t.vx = std::copysign(cfg_.escape_speed_mps, shift);
    return t;
  }
  escaping_ = false;  // nowhere near: hold (the stuck check ends it)
  return t;
}

MissionOutput WaypointMission::drive(const MissionContext& ctx, const Pose2& pose) {
  if (check_target_ || costmap().updates() != seen_updates_) {
    check_target_ = false;
    seen_updates_ = costmap().updates();
    if (target_in_obstacle()) return unreachable(ctx, pose, Fault::GoalInvalid, "goal_invalid");
  }
  const Vec2& target = cfg_.targets[target_];
  const Vec2 here(pose.x, pose.y);
  const double dist = (target - here).norm();
  if (dist <= cfg_.reach_radius_m || vff_.at_end()) {
    ++reached_;
    return next_target(ctx, pose);
  }
  // Progress: closer to the target than ever, or, going round an obstacle, along its edge.
  if (dist < best_dist_ - cfg_.stuck_progress_m ||
      (bypass_ && (here - progress_at_).norm() >= cfg_.stuck_progress_m)) {
    best_dist_ = std::fmin(best_dist_, dist);
    progress_t_ = ctx.t_s;
    progress_at_ = here;
  }
  if (ctx.t_s - progress_t_ > cfg_.stuck_time_s) {
    return unreachable(ctx, pose, Fault::NoPath, "stuck");
  }
  if (!bypass_) closest_ = std::fmin(closest_, dist);
  if (ctx.t_s - target_t0_ > cfg_.target_timeout_s) {
    return unreachable(ctx, pose, Fault::NoPath, "timeout");
  }

  // After a skip: DRIVE for a tick at least (a phase change a tick is reported).
  const bool skipped = !bypass_ && phase_.current() != kDrive;
  if (skipped) go(State::Drive, kDrive);
  guard_.gather(pose, costmap().master());
  const Vec2 to_target = (target - here) / dist;
  // The target alone is the path: the pull is straight at it.
  Twist want = vff_.update(pose, &target, 1, costmap().master());
  if (bypass_) {
    const double from = (here - bypass_from_).norm();
    bypass_left_ = bypass_left_ || from > kAwayM;
    if (bypass_left_ && from < kCircledM) return unreachable(ctx, pose, Fault::NoPath, "stuck");
  } else if (cfg_.bypass && !skipped && in_the_way(pose, to_target, dist)) {
    start_bypass(pose, to_target);
  }
  if (bypass_) {
    const BodyGuard::Nearest edge = follow_edge(pose);
    if (bypass_over(pose, edge, to_target, dist)) {
      bypass_ = false;
      go(State::Drive, kDrive);
    } else {
      want = bypass_twist(edge);
    }
  }
  MissionOutput out;
  bool blocked_straight = false;
  out.motion.twist = guarded(want, blocked_straight);
  // Held straight on short of something VFF does not steer off (its local minimum): round it,
  // unless the target is at it.
  if (blocked_straight && !bypass_ && cfg_.bypass && !skipped) {
    const BodyGuard::Nearest n = guard_.nearest();
    if (n.found && (to_world(pose, n.p) - target).norm() > keep_m()) {
      start_bypass(pose, to_target);
      out.motion.twist = guarded(bypass_twist(follow_edge(pose)), blocked_straight);
    }
  }
  return out;
}

}  // namespace carril::fw
