#include "firmware/mission/GotoMission.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/MissionStates.hpp"
#include "firmware/mission/ObstacleGuard.hpp"
#include "firmware/planning/PathWaypoints.hpp"

namespace carril::fw {

namespace {

// The corner check: an arc is checked for what it drives in kCornerReactionS plus
// emergency_stop_m, a turn in place for what it turns in kCornerReactionS (the margins, the
// tightest arc and the escape search: BodyGuard's constants).
constexpr double kCornerReactionS = 0.2;  // [s]

// The same ranges as the single goal's, naming the goal's index.
Status validate_goal(std::size_t k, const Pose2& g) {
  const struct {
    const char* field;
    double v, limit;
    const char* unit;
  } checks[] = {{"x", g.x, 1000.0, "m"}, {"y", g.y, 1000.0, "m"}, {"yaw", g.yaw, 2.0 * kPi, "rad"}};
  for (const auto& ch : checks) {
    if (!std::islessequal(std::fabs(ch.v), ch.limit)) {
      return Status::error("goto.goals[%zu].%s: %g %s, expected %g to %g %s", k, ch.field, ch.v,
                           ch.unit, -ch.limit, ch.limit, ch.unit);
    }
  }
  return Status::ok();
}

}  // namespace

Status GotoConfig::validate() const {
  Checks c("goto");
  c.range("speed_mps", speed_mps, 0.01, 5.0, "m/s")
      .range("goal_tolerance_m", goal_tolerance_m, 0.005, 1.0, "m")
      .range("goal_aim_m", goal_aim_m, 0.001, goal_tolerance_m, "m")
      .range("approach_settle_s", approach_settle_s, 0.0, 60.0, "s")
      .range("yaw_tolerance_rad", yaw_tolerance_rad, 0.001, 1.0, "rad")
      .range("approach_m", approach_m, 0.05, 5.0, "m")
      .range("goal_clear_m", goal_clear_m, 0.0, 2.0, "m")
      .range("replan_lookahead_m", replan_lookahead_m, 0.1, 50.0, "m")
      .range("emergency_stop_m", emergency_stop_m, 0.0, 1.0, "m")
      .range("backup_m", backup_m, 0.0, 2.0, "m")
      .range("backup_speed_mps", backup_speed_mps, 0.01, 1.0, "m/s")
      .range("max_recoveries", double(max_recoveries), 0.0, 1000.0, "stops")
      .range("turn_in_place_min_radps", turn_in_place_min_radps, 0.0, 10.0, "rad/s")
      .range("vff_fallback_m", vff_fallback_m, 0.0, 10.0, "m")
      .range("corner_pad_m", corner_pad_m, -1.0, 0.5, "m")
      .range("plan_expansions_per_tick", double(plan_expansions_per_tick), 100.0, 1e7, "cells")
      .range("goal.x", goal.x, -1000.0, 1000.0, "m")
      .range("goal.y", goal.y, -1000.0, 1000.0, "m")
      .range("goal.yaw", goal.yaw, -2.0 * kPi, 2.0 * kPi, "rad")
      .nested(planner.validate())
      .nested(pure_pursuit.validate())
      .nested(vff.validate())
      .nested(tracker.validate());
  for (std::size_t k = 0; k < goals.size(); ++k) c.nested(validate_goal(k, goals[k]));
  return c.result();
}

const char* goto_state_name(GotoMission::State s) {
  switch (s) {
    case GotoMission::State::Wait:
      return "WAIT";
    case GotoMission::State::Plan:
      return "PLAN";
    case GotoMission::State::Follow:
      return "FOLLOW";
    case GotoMission::State::Backup:
      return "BACKUP";
    case GotoMission::State::Approach:
      return "APPROACH";
    case GotoMission::State::Align:
      return "ALIGN";
    case GotoMission::State::Done:
      return "DONE";
    case GotoMission::State::Failed:
      return "FAILED";
  }
  return "?";
}

GotoMission::GotoMission(const GotoConfig& cfg, const Footprint& footprint, bool holonomic,
                         const Topic<OdometryMsg>& odom, const Topic<CostmapMsg>& costmap)
    : cfg_(cfg),
      footprint_(footprint),
      tracker_(cfg.tracker, holonomic),
      pure_pursuit_(cfg.pure_pursuit),
      vff_(cfg.vff),
      odom_(odom),
      costmap_in_(costmap),
      guard_(footprint.half_length_m, footprint.half_width_m, std::max(0.0, cfg.corner_pad_m),
             footprint.circumscribed_m() + std::max(0.0, cfg.corner_pad_m) +
                 cfg.speed_mps * kCornerReactionS + cfg.emergency_stop_m + BodyGuard::kEscapeM +
                 0.1),
      goal_(cfg.goal_at(0)) {
  // The view is on the bus before any mission is built (Mapping publishes it at init); none: no
  // costmap is built, and the mission cannot plan (validate() refuses goto without one).
  const CostmapView* view = costmap.get().view;
  if (view == nullptr) return;
  const RollingGrid<std::uint8_t>& m = view->master();
  planner_ready_ = m.ready() && planner_.init(m.nx(), m.ny(), cfg.planner);
  if (planner_ready_) plan_costs_ = std::make_unique<std::uint8_t[]>(std::size_t(m.nx()) * m.ny());
}

void GotoMission::go(State s, const char* phase) {
  if (s != state_) {
    escaping_ = false;
    settling_s_ = 0.0;
  }
  phase_.set(phase, s != state_);
  state_ = s;
}

void GotoMission::enter(const MissionContext&) {
  state_ = State::Wait;
  phase_.restart("wait");
  waypoints_.clear();
  cells_.clear();
  plans_ = replans_ = emergency_stops_ = vff_fallbacks_ = corner_turns_ = corner_escapes_ = 0;
  stops_.reset();
  vff_held_ = escaping_ = corner_held_ = false;
  fault_ = Fault::None;
  goal_index_ = 0;
  goal_ = cfg_.goal_at(0);
  goals_reached_ = 0;
}

MissionState GotoMission::state() const {
  // Onto the last goal; an intermediate one is still the task under way.
  const bool finishing = (state_ == State::Approach || state_ == State::Align) && last_goal();
  return report_state(state_, goto_state_name(state_), phase_,
                      finishing ? MissionStatus::Finishing : MissionStatus::Active);
}

void GotoMission::counters(MissionCounters& out) const {
  out.clear();
  out.push_back({"plans", plans_});
  out.push_back({"replans", replans_});
  out.push_back({"emergency_stops", emergency_stops_});
  out.push_back({"goals_reached", goals_reached_});
  out.push_back({"vff_fallbacks", vff_fallbacks_});
  out.push_back({"corner_turns", corner_turns_});
  out.push_back({"corner_escapes", corner_escapes_});
}

void GotoMission::relocalised() {
  switch (state_) {
    case State::Follow:
    case State::Backup:
    case State::Approach:
    case State::Align:
      ++replans_;
      stops_.reset();  // stops seen from the wrong pose say nothing about this one
      waypoints_.clear();
      go(State::Plan, "replan");
      break;
    case State::Wait:
    case State::Plan:
    case State::Done:
    case State::Failed:
      break;
  }
}

MissionOutput GotoMission::fail(Fault f) {
  fault_ = f;
  go(State::Failed, f == Fault::NoPath ? "no_path" : "goal_invalid");
  return fault_output(f);
}

// Goal k is reached: DONE after the last one, else a plan to goal k + 1 from here.
MissionOutput GotoMission::goal_reached(const Pose2& pose) {
  ++goals_reached_;
  if (last_goal()) {
    go(State::Done, "done");
    return {};
  }
  goal_ = cfg_.goal_at(++goal_index_);
  stops_.reset();  // reaching a goal is progress
  go(State::Plan, "plan");
  return plan_step(pose);
}

MissionOutput GotoMission::update(const MissionContext& ctx) {
  const Pose2 pose = odom_.get().pose;
  switch (state_) {
    case State::Wait:
      if (ctx.drives_ready && costmap().updates() > 0) {
        if (!planner_ready_) return fail(Fault::NoPath);
        go(State::Plan, "plan");
        return plan_step(pose);
      }
      return {};
    case State::Plan:
      return plan_step(pose);
    case State::Follow:
      return follow(pose, ctx.guard);
    case State::Backup:
      return backup(pose);
    case State::Approach: {
      bool arrived = false;
      MissionOutput out;
      out.motion.twist =
          tracker_.approach(pose, goal_xy(), cfg_.speed_mps, 1.5, cfg_.goal_aim_m, arrived);
      // Settles only for time spent within the tolerance in a row.
      if ((Vec2(pose.x, pose.y) - goal_xy()).norm() > cfg_.goal_tolerance_m) {
        settling_s_ = 0.0;
      } else if (!arrived) {
        settling_s_ += ctx.dt_s;
        arrived = settling_s_ >= cfg_.approach_settle_s;
      }
      if (!arrived) return out;
      if (last_goal() || cfg_.align_every_goal) {
        go(State::Align, "align");
        return out;
      }
      return goal_reached(pose);
    }
    case State::Align: {
      MissionOutput out;
      if (std::fabs(wrap_angle(goal_.yaw - pose.yaw)) <= cfg_.yaw_tolerance_rad) {
        return goal_reached(pose);
      }
      out.motion.twist = tracker_.turn_to(pose, goal_.yaw);
      return out;
    }
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

// The robot's cell for the descent: its own, or when that one is impassable (the robot stands
// in an obstacle's inflation) the neighbour within 3 cells nearest the goal.
bool GotoMission::start_cell(const Pose2& pose, GridCell& out) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  const int x0 = m.cell_of(pose.x) - plan_cx0_, y0 = m.cell_of(pose.y) - plan_cy0_;
  if (planner_.reachable(x0, y0)) {
    out = {x0, y0};
    return true;
  }
  float best = WavefrontPlanner::kInfinity;
  for (int dy = -3; dy <= 3; ++dy) {
    for (int dx = -3; dx <= 3; ++dx) {
      if (!planner_.reachable(x0 + dx, y0 + dy)) continue;
      const float c = planner_.cost_to_goal(x0 + dx, y0 + dy);
      if (c < best) {
        best = c;
        out = {x0 + dx, y0 + dy};
      }
    }
  }
  return best < WavefrontPlanner::kInfinity;
}

// The robot standing on the goal would touch something the 2D lidar has seen: a lethal obstacle
// cell within the footprint's circumscribed radius of the goal.
bool GotoMission::goal_in_obstacle(int gx, int gy) const {
  // What a body on the goal could touch: the lidar's returns and the static map's walls.
  const double radius = footprint_.circumscribed_m();
  for (const RollingGrid<std::uint8_t>* g : {&costmap().obstacles(), costmap().walls()}) {
    if (g == nullptr || !g->ready()) continue;
    const int r = static_cast<int>(std::ceil(radius / g->resolution()));
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        if (std::hypot(dx, dy) * g->resolution() > radius) continue;
        if (g->contains(gx + dx, gy + dy) && g->at(gx + dx, gy + dy) == cost::kLethal) return true;
      }
    }
  }
  return false;
}

MissionOutput GotoMission::plan_step(const Pose2& pose) {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  if (planner_.status() != WavefrontStatus::Running) {
    // A new plan on the current costmap.
    int gx = 0, gy = 0;
    if (!m.world_to_cell(goal_.x, goal_.y, gx, gy)) return fail(Fault::GoalInvalid);
    if (goal_in_obstacle(gx, gy)) return fail(Fault::GoalInvalid);
    m.copy_to(plan_costs_.get());
    const int r = static_cast<int>(std::ceil(cfg_.goal_clear_m / m.resolution()));
    const int lgx = gx - m.origin_cx(), lgy = gy - m.origin_cy();
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const int x = lgx + dx, y = lgy + dy;
        if (x < 0 || y < 0 || x >= m.nx() || y >= m.ny() || dx * dx + dy * dy > r * r) continue;
        // The lidar layer may be a smaller window than the master (a fixed map of a building
        // round a rolling lidar window): a cell outside it has not been seen.
        const RollingGrid<std::uint8_t>& o = costmap().obstacles();
        const int cx = m.origin_cx() + x, cy = m.origin_cy() + y;
        if (o.contains(cx, cy) && o.at(cx, cy) == cost::kLethal) continue;
        // Nor is a wall of the static map ever cleared.
        const RollingGrid<std::uint8_t>* w = costmap().walls();
        if (w != nullptr && w->contains(cx, cy) && w->at(cx, cy) == cost::kLethal) continue;
        std::uint8_t& c = plan_costs_[std::size_t(y) * std::size_t(m.nx()) + std::size_t(x)];
        if (!cost::passable(c)) c = cost::kMaxGraded;
      }
    }
    const WavefrontStatus s = planner_.start(plan_costs_.get(), m.nx(), m.ny(), lgx, lgy);
    if (s == WavefrontStatus::GoalOutside || s == WavefrontStatus::GoalBlocked ||
        s == WavefrontStatus::BadGrid) {
      return fail(Fault::GoalInvalid);
    }
    plan_cx0_ = m.origin_cx();
    plan_cy0_ = m.origin_cy();
    // No early stop at the robot's cell: when it stands in inflation a neighbour is taken.
    ++plans_;
    return {};  // copying the costmap and seeding the planner are this tick's work
  }
  const WavefrontStatus s = planner_.step(cfg_.plan_expansions_per_tick);
  if (s == WavefrontStatus::Running) return {};  // stopped while planning
  GridCell start;
  if (!start_cell(pose, start)) return fail(Fault::NoPath);
  if (planner_.extract_path(start.x, start.y, cells_) != PathResult::Ok) {
    return fail(Fault::NoPath);
  }
  const double ox = plan_cx0_ * m.resolution(), oy = plan_cy0_ * m.resolution();
  cells_to_waypoints(cells_.begin(), cells_.size(), ox, oy, m.resolution(), waypoints_);
  // The goal itself, not its cell's centre, ends the path.
  if (!waypoints_.empty()) waypoints_.back() = goal_xy();
  progress_ = 0;
  pure_pursuit_.reset();
  vff_.reset();
  vff_held_ = false;
  seen_updates_ = costmap().updates();
  go(State::Follow, "follow");
  return {};
}

// Samples the path from the robot's segment on, for replan_lookahead_m: a lethal or inscribed
// cell on it means the plan no longer holds.
bool GotoMission::path_blocked_ahead(const Pose2& pose) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  return fw::path_blocked_ahead(
      pose, waypoints_.begin(), waypoints_.size(), progress_ + 1, cfg_.replan_lookahead_m,
      0.5 * m.resolution(), footprint_.half_width_m, [&](const Vec2& p) {
        int cx = 0, cy = 0;
        if (!m.world_to_cell(p.x(), p.y(), cx, cy)) return false;
        const std::uint8_t c = m.at(cx, cy);
        const bool near_goal = (p - goal_xy()).norm() <= cfg_.goal_clear_m;
        return !near_goal && (c == cost::kLethal || c == cost::kInscribed);
      });
}

// A lethal cell just ahead of the body (within emergency_stop_m of its front edge).
bool GotoMission::lethal_ahead(const Pose2& pose) const {
  return lethal_at_edge(pose, footprint_.half_length_m + cfg_.emergency_stop_m);
}

// A lethal cell on the body's cross line at x_body (body frame) [m], across its width.
bool GotoMission::lethal_at_edge(const Pose2& pose, double x_body) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  // Samples every half cell across the width, both edges included.
  const int n = static_cast<int>(std::ceil(2.0 * footprint_.half_width_m / (0.5 * m.resolution())));
  for (int k = 0; k <= n; ++k) {
    const double y = -footprint_.half_width_m + 2.0 * footprint_.half_width_m * k / std::max(n, 1);
    const Vec2 p = to_world(pose, Vec2(x_body, y));
    if ((p - goal_xy()).norm() <= cfg_.goal_clear_m) continue;
    int cx = 0, cy = 0;
    if (m.world_to_cell(p.x(), p.y(), cx, cy) && m.at(cx, cy) == cost::kLethal) return true;
  }
  return false;
}

// The costmap says the body is about to touch something: stop, back off, plan again; give up
// after max_recoveries stops in a row without getting anywhere.
MissionOutput GotoMission::emergency_stop(const Pose2& pose) {
  ++emergency_stops_;
  const Vec2 here(pose.x, pose.y);
  if (stops_.too_many(here, 2.0 * cfg_.backup_m, cfg_.max_recoveries)) return fail(Fault::NoPath);
  backup_from_ = here;
  go(State::Backup, "backup");
  return {};
}

MissionOutput GotoMission::backup(const Pose2& pose) {
  const bool far_enough = (Vec2(pose.x, pose.y) - backup_from_).norm() >= cfg_.backup_m;
  if (far_enough || lethal_at_edge(pose, -(footprint_.half_length_m + cfg_.emergency_stop_m))) {
    ++replans_;
    go(State::Plan, "replan");
    return plan_step(pose);
  }
  MissionOutput out;
  out.motion.twist.vx = -cfg_.backup_speed_mps;
  return out;
}

MissionOutput GotoMission::follow(const Pose2& pose, const ObstacleGuard* lidar) {
  if ((goal_xy() - Vec2(pose.x, pose.y)).norm() <= cfg_.approach_m) {
    go(State::Approach, "approach");
    return {};
  }
  if (costmap().updates() != seen_updates_) {
    seen_updates_ = costmap().updates();
    if (path_blocked_ahead(pose)) {
      ++replans_;
      go(State::Plan, "replan");
      return plan_step(pose);
    }
  }
  MissionOutput out;
  bool at_end = false;
  const bool front_lethal = lethal_ahead(pose);  // for the handover and the stop below
  if (cfg_.follower == GotoFollower::Vff) {
    // Both run every tick, so each keeps its place on the path; VFF drives unless its heading
    // has met a lethal cell within the last vff_fallback_m.
    const Twist pp = pure_pursuit_.update(pose, waypoints_.begin(), waypoints_.size());
    out.motion.twist = vff_.update(pose, waypoints_.begin(), waypoints_.size(), costmap().master());
    const Vec2 here(pose.x, pose.y);
    if (vff_held_ && (here - vff_held_at_).norm() >= cfg_.vff_fallback_m) vff_held_ = false;
    if (!vff_held_ && cfg_.vff_fallback_m > 0.0 && out.motion.twist.vx > 0.0 && front_lethal) {
      vff_held_ = true;
      vff_held_at_ = here;
      ++vff_fallbacks_;
    }
    if (vff_held_) {
      out.motion.twist = pp;
      progress_ = pure_pursuit_.progress();
      at_end = pure_pursuit_.at_end();
    } else {
      progress_ = vff_.progress();
      at_end = vff_.at_end();
    }
  } else {
    out.motion.twist = pure_pursuit_.update(pose, waypoints_.begin(), waypoints_.size());
    progress_ = pure_pursuit_.progress();
    at_end = pure_pursuit_.at_end();
  }
  if (out.motion.twist.vx > 0.0 && front_lethal) {
    // Turning toward the path: do it in place (the front is what is close). Heading straight
    // on into the cell: stop, back off and plan again.
    if (std::fabs(out.motion.twist.wz) >= cfg_.turn_in_place_min_radps) {
      out.motion.twist.vx = 0.0;
      out.motion.twist.vy = 0.0;
      return corner_guarded(pose, out, lidar);
    }
    return emergency_stop(pose);
  }
  if (at_end) go(State::Approach, "approach");
  return corner_guarded(pose, out, lidar);
}

// A tight turn checked with the corners (see corner_pad_m); other commands pass unchanged.
MissionOutput GotoMission::corner_guarded(const Pose2& pose, MissionOutput out,
                                          const ObstacleGuard* lidar) {
  Twist& t = out.motion.twist;
  const Vec2 here(pose.x, pose.y);
  const bool tight =
      cfg_.corner_pad_m >= 0.0 && t.vx >= 0.0 && std::fabs(t.wz) >= cfg_.turn_in_place_min_radps;
  if (escaping_ || tight) {
    guard_.gather(pose, costmap().obstacles());
    // What the lidar saw before it left its view: a 180 deg lidar is blind beside and behind,
    // where a turn's corners sweep, and a relocalisation clears the costmap's marks.
    if (lidar != nullptr && lidar->field().valid()) {
      const auto& m = lidar->field().remembered();
      guard_.add_points(m.begin(), m.size(), lidar->odom_pose());
    }
  }
  if (escaping_) {
    // An escape runs its distance (deciding afresh each tick flips between ahead and back where
    // the two are about as good), unless something now stands in its way.
    const double left = escape_m_ - (here - escape_from_).norm();
    if (left > 0.0 && guard_.free_length(0.0, escape_dir_ < 0.0, left) >= left) {
      t = Twist{};
      t.vx = escape_dir_ * cfg_.backup_speed_mps;
      return out;
    }
    escaping_ = false;
  }
  if (!tight) {
    corner_held_ = false;
    return out;
  }
  const double turn =
      std::copysign(std::fabs(t.wz) * kCornerReactionS + BodyGuard::kTurnMarginRad, t.wz);
  if (t.vx > 0.0) {
    const double k = std::clamp(t.wz / t.vx, -BodyGuard::kMaxCurvature, BodyGuard::kMaxCurvature);
    const double reach = t.vx * kCornerReactionS + cfg_.emergency_stop_m;
    if (guard_.free_length(k, false, reach) >= reach) {
      corner_held_ = false;
      return out;
    }
    // The arc would bring the body onto a cell: turning in place keeps the front back.
    if (!corner_held_) ++corner_turns_;
    corner_held_ = true;
    t.vx = 0.0;
    t.vy = 0.0;
  } else {
    corner_held_ = false;
  }
  if (guard_.rotation_clear(turn)) return out;
  // A corner would touch: move straight to the nearest place from which the turn is clear
  // (behind first: the robot came from there).
  const double shift = guard_.escape_shift(turn, BodyGuard::kEscapeStepM, BodyGuard::kEscapeM, 0.0);
  if (shift == 0.0) return emergency_stop(pose);
  ++corner_escapes_;
  escaping_ = true;
  escape_dir_ = shift < 0.0 ? -1.0 : 1.0;
  escape_from_ = here;
  escape_m_ = std::fabs(shift);
  t = Twist{};
  t.vx = escape_dir_ * cfg_.backup_speed_mps;
  return out;
}

}  // namespace carril::fw
