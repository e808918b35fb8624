#include "firmware/mission/WaypointMission.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {

// DRIVE's phases (compared by address).
constexpr const char* kDrive = "drive";
constexpr const char* kBypass = "bypass";
constexpr const char* kSkip = "skip";  // one tick: a target was given up, the next one is current

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
                                 const CostmapView& costmap)
    : cfg_(cfg),
      footprint_(footprint),
      holonomic_(holonomic),
      vff_(follower_config(cfg)),
      pose_(pose),
      costmap_(costmap) {}

void WaypointMission::go(State s, const char* phase) {
  if (s != state_ || phase != phase_) phase_change_ = phase;
  state_ = s;
  phase_ = phase;
}

const char* WaypointMission::take_phase_change() {
  const char* p = phase_change_;
  phase_change_ = nullptr;
  return p;
}

void WaypointMission::enter(const MissionContext&) {
  state_ = State::Wait;
  phase_ = "wait";
  phase_change_ = "wait";
  target_ = 0;
  reached_ = skipped_ = laps_done_ = emergency_stops_ = 0;
  lap_times_.clear();
  stopped_ = bypass_ = false;
  bypasses_ = 0;
  fault_ = Fault::None;
}

MissionState WaypointMission::state() const {
  MissionState s;
  s.id = static_cast<std::uint8_t>(state_);
  s.name = waypoint_state_name(state_);
  s.phase = phase_;
  switch (state_) {
    case State::Wait:
      s.status = MissionStatus::Starting;
      break;
    case State::Drive: {
      const bool last = laps_done_ + 1 >= cfg_.laps && target_ + 1 >= cfg_.targets.size();
      s.status = last ? MissionStatus::Finishing : MissionStatus::Active;
      break;
    }
    case State::Done:
      s.status = MissionStatus::Done;
      break;
    case State::Failed:
      s.status = MissionStatus::Failed;
      break;
  }
  return s;
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
}

MissionOutput WaypointMission::fail(Fault f, const char* phase) {
  fault_ = f;
  go(State::Failed, phase);
  MissionOutput out;
  out.fault = f;
  return out;
}

MissionOutput WaypointMission::update(const MissionContext& ctx) {
  const Pose2 pose = pose_.get().pose;
  switch (state_) {
    case State::Wait:
      if (!ctx.drives_ready || costmap_.updates() == 0) return {};
      if (cfg_.targets.empty()) {
        go(State::Done, "done");
        return {};
      }
      // The emergency stop reads the master: without one the robot would drive blind.
      if (!costmap_.master().ready()) return fail(Fault::NoPath, "no_costmap");
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
  best_dist_ = (cfg_.targets[target_] - Vec2(pose.x, pose.y)).norm();
  check_target_ = true;
  stopped_ = false;
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
  const RollingGrid<std::uint8_t>& o = costmap_.obstacles();
  if (!o.ready()) return false;
  const Vec2& t = cfg_.targets[target_];
  int tx = 0, ty = 0;
  if (!o.world_to_cell(t.x(), t.y(), tx, ty)) return false;  // not seen yet
  const double circumscribed = std::hypot(footprint_.half_length_m, footprint_.half_width_m);
  const double radius = std::fmax(0.0, circumscribed - cfg_.reach_radius_m);
  const int r = static_cast<int>(std::ceil(radius / o.resolution()));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (std::hypot(dx, dy) * o.resolution() > radius && (dx != 0 || dy != 0)) continue;
      if (o.contains(tx + dx, ty + dy) && o.at(tx + dx, ty + dy) == cost::kLethal) return true;
    }
  }
  return false;
}

// A lethal master cell on the body's cross line emergency_stop_m ahead of its front edge,
// sampled every half cell across the width, both edges included.
bool WaypointMission::lethal_ahead(const Pose2& pose) const {
  const RollingGrid<std::uint8_t>& m = costmap_.master();
  const double x_body = footprint_.half_length_m + cfg_.emergency_stop_m;
  const double w = footprint_.half_width_m;
  const int n = std::max(1, static_cast<int>(std::ceil(2.0 * w / (0.5 * m.resolution()))));
  for (int k = 0; k <= n; ++k) {
    const Vec2 p = to_world(pose, Vec2(x_body, -w + 2.0 * w * k / n));
    int cx = 0, cy = 0;
    if (m.world_to_cell(p.x(), p.y(), cx, cy) && m.at(cx, cy) == cost::kLethal) return true;
  }
  return false;
}

MissionOutput WaypointMission::drive(const MissionContext& ctx, const Pose2& pose) {
  if (check_target_ || costmap_.updates() != seen_updates_) {
    check_target_ = false;
    seen_updates_ = costmap_.updates();
    if (target_in_obstacle()) return unreachable(ctx, pose, Fault::GoalInvalid, "goal_invalid");
  }
  const Vec2& target = cfg_.targets[target_];
  const double dist = (target - Vec2(pose.x, pose.y)).norm();
  if (dist <= cfg_.reach_radius_m || vff_.at_end()) {
    ++reached_;
    return next_target(ctx, pose);
  }
  if (dist < best_dist_ - cfg_.stuck_progress_m) {
    best_dist_ = dist;
    progress_t_ = ctx.t_s;
  }
  if (ctx.t_s - progress_t_ > cfg_.stuck_time_s) {
    return unreachable(ctx, pose, Fault::NoPath, "stuck");
  }
  if (ctx.t_s - target_t0_ > cfg_.target_timeout_s) {
    return unreachable(ctx, pose, Fault::NoPath, "timeout");
  }

  if (!bypass_ && phase_ != kDrive) go(State::Drive, kDrive);  // after a skip
  MissionOutput out;
  // The target alone is the path: the pull is straight at it.
  out.motion.twist = vff_.update(pose, &target, 1, costmap_.master());
  const bool blocked = lethal_ahead(pose);
  if (bypass_) {
    // Round the obstacle until it no longer stands between the robot and the target (the push
    // no longer opposes the pull) and the front is clear.
    const bool behind = vff_.attraction().dot(vff_.repulsion()) >= 0.0;
    if (!(behind && !blocked)) return bypass_step(pose, blocked);
    bypass_ = false;
    go(State::Drive, kDrive);
  }
  const bool stop = out.motion.twist.vx > 0.0 && blocked;
  if (stop) {
    if (!stopped_) ++emergency_stops_;
    out.motion.twist.vx = 0.0;
    out.motion.twist.vy = 0.0;
    // Turning: in place (the front is what is close). Straight on, into a local minimum of the
    // forces: round the obstacle, on the side the push leans to (left when it does not lean).
    if (std::fabs(out.motion.twist.wz) < cfg_.turn_in_place_min_radps) {
      out.motion.twist.wz = 0.0;
      const Vec2 r = vff_.repulsion();
      if (cfg_.bypass && r.squaredNorm() > 1e-12) {
        const double lateral = -std::sin(pose.yaw) * r.x() + std::cos(pose.yaw) * r.y();
        side_ = lateral < 0.0 ? -1 : 1;
        bypass_ = true;
        ++bypasses_;
        go(State::Drive, kBypass);
        stopped_ = stop;
        return bypass_step(pose, blocked);
      }
    }
  }
  stopped_ = stop;
  return out;
}

// Along the obstacle's edge: the heading square to the push, on side_; in place while that is
// far off the heading or the front is blocked.
MissionOutput WaypointMission::bypass_step(const Pose2& pose, bool blocked) const {
  MissionOutput out;
  const Vec2 r = vff_.repulsion();
  if (r.squaredNorm() < 1e-12) return out;  // the push is gone: the next tick leaves
  const Vec2 along = side_ > 0 ? Vec2(r.y(), -r.x()) : Vec2(-r.y(), r.x());
  const double err = wrap_angle(std::atan2(along.y(), along.x()) - pose.yaw);
  const VffConfig& v = cfg_.vff;
  Twist& t = out.motion.twist;
  t.wz = clampd(v.turn_gain * err, -v.max_yaw_rate_radps, v.max_yaw_rate_radps);
  if (blocked) {
    // Turning away from the obstacle's side clears the front.
    if (std::fabs(t.wz) < cfg_.turn_in_place_min_radps) t.wz = side_ * v.max_yaw_rate_radps;
    return out;
  }
  if (std::fabs(err) <= v.turn_in_place_rad) t.vx = cfg_.bypass_speed_mps * std::cos(err);
  return out;
}

}  // namespace carril::fw
