// The coverage mission: configuration, construction, the state machine's frame and the vacuum
// baseline. The systematic mode's planning and driving are in CoverageSystematic.cpp.
#include "firmware/mission/CoverageMission.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/MissionStates.hpp"

namespace carril::fw {

Status VacuumConfig::validate() const {
  return Checks("coverage.vacuum")
      .range("spiral_speed_mps", spiral_speed_mps, 0.01, 5.0, "m/s")
      .range("spiral_start_radius_m", spiral_start_radius_m, 0.01, 10.0, "m")
      .range("spiral_growth_mps", spiral_growth_mps, 0.0, 1.0, "m/s")
      .range("spiral_max_s", spiral_max_s, 0.0, 3600.0, "s")
      .range("backup_s", backup_s, 0.0, 60.0, "s")
      .range("backup_speed_mps", backup_speed_mps, 0.01, 2.0, "m/s")
      .range("turn_min_s", turn_min_s, 0.0, 60.0, "s")
      .range("turn_max_s", turn_max_s, turn_min_s, 60.0, "s")
      .range("turn_rate_radps", turn_rate_radps, 0.05, 10.0, "rad/s")
      .range("forward_speed_mps", forward_speed_mps, 0.01, 5.0, "m/s")
      .range("forward_s", forward_s, 0.1, 3600.0, "s")
      .range("bump_m", bump_m, 0.0, 1.0, "m")
      .result();
}

CoverageConfig::CoverageConfig() {
  sweep.cruise_speed_mps = speed_mps;
  sweep.max_yaw_rate_radps = 1.5;
  transit_pursuit.cruise_speed_mps = transit_speed_mps;
  transit_pursuit.slow_radius_m = 0.2;
  // Short: a long lookahead cuts the corners of doors. Facing more than 0.4 rad away from the
  // pursued point, turn on the spot: an arc started that far off heads into the wall beside a
  // lane's end.
  transit_pursuit.lookahead_m = 0.3;
  transit_pursuit.rotate_in_place_rad = 0.4;
  // Turns on the spot at a transit's start take a tenth of the run at the default gain of 2.
  transit_pursuit.turn_gain = 3.0;
}

Status CoverageConfig::validate() const {
  Checks c("coverage");
  c.range("tool_width_m", tool_width_m, 0.05, 5.0, "m")
      .range("speed_mps", speed_mps, 0.01, 5.0, "m/s")
      .range("transit_speed_mps", transit_speed_mps, 0.01, 5.0, "m/s")
      .range("transit_edge_margin_m", transit_edge_margin_m, 0.0, 2.0, "m")
      .range("transit_edge_lookahead_m", transit_edge_lookahead_m, 0.0, 5.0, "m")
      .range("lane_overlap", lane_overlap, 0.0, 0.9, "")
      .range("turn_radius_m", turn_radius_m, 0.0, 5.0, "m")
      .range("join_max_gap_m", join_max_gap_m, 0.0, 10.0, "m")
      .range("join_max_step_m", join_max_step_m, 0.0, 1.0, "m")
      .range("wall_clearance_m", wall_clearance_m, 0.0, 1.0, "m")
      .fail_if(area.size() > 0 && area.size() < 3, "area", "a polygon needs 3 corners or more")
      .range("target_coverage", target_coverage, 0.0, 1.0, "")
      .range("skip_swept_cell", skip_swept_cell, 0.0, 1.0, "")
      .range("max_revisits", double(max_revisits), 0.0, 100000.0, "targets")
      .range("revisit_min_area_m2", revisit_min_area_m2, 0.0, 100.0, "m^2")
      .range("revisit_spin_rad", revisit_spin_rad, 0.0, 4.0 * kPi, "rad")
      .range("spin_rate_radps", spin_rate_radps, 0.05, 10.0, "rad/s")
      .range("max_time_s", max_time_s, 0.0, 1e6, "s")
      .range("plan_expansions_per_tick", double(plan_expansions_per_tick), 100.0, 1e7, "cells")
      .range("block_lookahead_m", block_lookahead_m, 0.05, 10.0, "m")
      .range("resume_clear_m", resume_clear_m, 0.0, 5.0, "m")
      .range("replan_lookahead_m", replan_lookahead_m, 0.1, 50.0, "m")
      .range("emergency_stop_m", emergency_stop_m, 0.0, 1.0, "m")
      .range("backup_m", backup_m, 0.0, 2.0, "m")
      .range("backup_speed_mps", backup_speed_mps, 0.01, 1.0, "m/s")
      .range("max_recoveries", double(max_recoveries), 0.0, 1000.0, "stops")
      .range("turn_in_place_min_radps", turn_in_place_min_radps, 0.0, 10.0, "rad/s")
      .range("mapped_wall_tolerance_m", mapped_wall_tolerance_m, 0.0, 1.0, "m")
      .range("max_cells", double(max_cells), 1.0, double(Boustrophedon::kMaxCellsLimit), "cells")
      .range("max_lanes", double(max_lanes), 1.0, 1e6, "lanes")
      .nested(vacuum.validate())
      .nested(sweep.validate())
      .nested(transit_pursuit.validate())
      .nested(tracker.validate())
      .nested(planner.validate());
  return c.result();
}

const char* coverage_state_name(CoverageMission::State s) {
  switch (s) {
    case CoverageMission::State::Wait:
      return "WAIT";
    case CoverageMission::State::Plan:
      return "PLAN";
    case CoverageMission::State::Transit:
      return "TRANSIT";
    case CoverageMission::State::Sweep:
      return "SWEEP";
    case CoverageMission::State::Spin:
      return "SPIN";
    case CoverageMission::State::Reverse:
      return "REVERSE";
    case CoverageMission::State::Spiral:
      return "SPIRAL";
    case CoverageMission::State::BackUp:
      return "BACK_UP";
    case CoverageMission::State::Turn:
      return "TURN";
    case CoverageMission::State::Forward:
      return "FORWARD";
    case CoverageMission::State::Done:
      return "DONE";
    case CoverageMission::State::Failed:
      return "FAILED";
  }
  return "?";
}

namespace {
std::size_t map_cells(const OccupancyGrid& m) {
  return m.empty() ? 0 : std::size_t(m.nx()) * std::size_t(m.ny());
}
}  // namespace

CoverageMission::CoverageMission(const CoverageConfig& cfg, const Footprint& footprint,
                                 bool holonomic, const Topic<OdometryMsg>& pose,
                                 const Topic<CostmapMsg>& costmap, const OccupancyGrid& static_map)
    : cfg_(cfg),
      footprint_(footprint),
      tracker_(cfg.tracker, holonomic),
      sweep_follower_(cfg.sweep),
      transit_follower_(cfg.transit_pursuit),
      pose_(pose),
      costmap_in_(costmap),
      map_(static_map),
      area_(map_cells(static_map)) {
  init_status_ = cfg.validate();
  if (!init_status_) return;
  const bool systematic = cfg.mode == CoverageMode::Systematic;
  if (static_map.empty()) {
    // The vacuum runs blind without a map; it only cannot count its coverage.
    if (systematic) init_status_ = Status::error("coverage: no static map (map.file) to plan on");
    return;
  }
  CoverageAreaConfig ac;
  ac.robot_radius_m =
      std::min(footprint.half_length_m, footprint.half_width_m) + cfg.wall_clearance_m;
  ac.tool_width_m = cfg.tool_width_m;
  ac.box_distance = true;  // clear of door jambs' corners as of walls
  // Transits may leave the polygon: the planner's area is the whole map's.
  Status s = area_.build(static_map, ac);
  const std::size_t n = map_cells(static_map);
  if (s) {
    base_costs_ = std::make_unique<std::uint8_t[]>(n);
    for (std::size_t k = 0; k < n; ++k)
      base_costs_[k] = area_.centre()[k] != 0 ? cost::kFree : cost::kLethal;
    if (cfg.area.size() > 0) {
      ac.polygon = cfg.area.begin();
      ac.polygon_size = cfg.area.size();
      s = area_.build(static_map, ac);
    }
  }
  if (!s) {
    if (systematic) init_status_ = s;
    return;
  }
  const int nx = static_map.nx(), ny = static_map.ny();
  if (Status g = coverage_.init(static_map.info()); !g) {
    init_status_ = g;
    return;
  }
  if (!planner_.init(nx, ny, cfg.planner)) {
    init_status_ = Status::error("coverage: planner buffers for %d x %d cells", nx, ny);
    return;
  }
  plan_costs_ = std::make_unique<std::uint8_t[]>(n);
  abandoned_ = std::make_unique<std::uint8_t[]>(n);
  mapped_ = std::make_unique<std::uint8_t[]>(n);
  build_mapped_mask();
  accounting_ = true;
  if (!systematic) return;
  // The revisits' patch measure (systematic only).
  patch_size_ = std::make_unique<std::uint32_t[]>(n);
  patch_queue_ = std::make_unique<std::uint32_t[]>(n);
  BoustrophedonConfig bc;
  bc.lane_spacing_m = cfg.tool_width_m * (1.0 - cfg.lane_overlap);
  bc.turn_radius_m = cfg.turn_radius_m;
  const MapInfo& info = static_map.info();
  init_status_ = bcd_.init(nx, ny, cfg.max_cells, cfg.max_lanes);
  if (init_status_) {
    init_status_ = bcd_.decompose(area_.centre(), nx, ny, info.resolution_m, info.origin_x_m,
                                  info.origin_y_m, bc);
  }
  if (!init_status_) {
    accounting_ = false;
    return;
  }
  // Every cell's route must fit the route buffer (the longest: many lanes and their U-turns).
  for (std::size_t k = 0; k < bcd_.cell_count(); ++k) {
    if (!bcd_.route(CellVisit{std::uint16_t(k), 0}, route_)) {
      init_status_ = Status::error(
          "coverage: cell %zu of the area needs more than %zu route waypoints (cover the "
          "area in parts: coverage.area)",
          k, kMaxRoute);
      accounting_ = false;
      return;
    }
  }
  route_.clear();
  // The tour starts at the map's lower-left corner; PLAN drives it backwards when its other end
  // is nearer the robot.
  bcd_.order(Vec2(info.origin_x_m, info.origin_y_m));
}

void CoverageMission::go(State s, const char* phase) {
  phase_.set(phase, s != state_);
  if (s != state_) state_t0_s_ = now_s_;
  state_ = s;
}

void CoverageMission::enter(const MissionContext& ctx) {
  now_s_ = ctx.t_s;
  state_ = State::Wait;
  phase_.restart("wait");
  t0_s_ = -1.0;
  have_last_ = false;
  planning_ = false;
  tour_pos_ = 0;
  rng_ = cfg_.seed != 0 ? cfg_.seed : 1u;
  cells_done_ = lanes_ = lanes_blocked_ = revisits_ = bumps_ = replans_ = joins_ = 0;
  turns_left_ = turns_right_ = 0;
  stops_.reset();
  fault_ = Fault::None;
  if (accounting_) {
    coverage_.clear();
    for (std::size_t k = 0; k < area_.size(); ++k) abandoned_[k] = 0;
  }
}

MissionState CoverageMission::state() const {
  return report_state(state_, coverage_state_name(state_), phase_, MissionStatus::Active,
                      state_ == State::Sweep);
}

void CoverageMission::counters(MissionCounters& out) const {
  out.clear();
  out.push_back({"cells", cells_done_});
  out.push_back({"lanes", lanes_});
  out.push_back({"lanes_blocked", lanes_blocked_});
  out.push_back({"revisits", revisits_});
  out.push_back({"bumps", bumps_});
  out.push_back({"replans", replans_});
  out.push_back(
      {"covered_permille", std::uint32_t(std::lround(1000.0 * coverage_.covered_fraction()))});
  out.push_back(
      {"overlap_permille", std::uint32_t(std::lround(1000.0 * coverage_.overlap_fraction()))});
  out.push_back({"joins", joins_});
}

MissionOutput CoverageMission::fail(Fault f) {
  fault_ = f;
  go(State::Failed, fault_name(f));
  return fault_output(f);
}

std::size_t CoverageMission::cell_index(int i, int j) const {
  return std::size_t(j) * std::size_t(map_.nx()) + std::size_t(i);
}

MissionOutput CoverageMission::update(const MissionContext& ctx) {
  now_s_ = ctx.t_s;
  const Pose2 pose = pose_.get().pose;
  if (state_ == State::Done) return {};
  if (state_ == State::Failed) return fail(fault_);
  if (state_ != State::Wait) {
    if (accounting_ && have_last_) coverage_.sweep(last_pose_, pose, cfg_.tool_width_m);
    last_pose_ = pose;
    have_last_ = true;
    if (cfg_.max_time_s > 0.0 && now_s_ - t0_s_ >= cfg_.max_time_s) {
      go(State::Done, "time_limit");
      return {};
    }
  }
  switch (state_) {
    case State::Wait:
      if (!ctx.drives_ready || costmap().updates() == 0) return {};
      if (!init_status_) return fail(Fault::NoCoverageArea);
      t0_s_ = now_s_;
      last_pose_ = pose;
      have_last_ = true;
      if (accounting_) return start_plan(Purpose::Initial, pose);
      go(State::Spiral, "spiral");
      return {};
    case State::Plan:
      return plan_step(pose);
    case State::Transit:
      return transit(pose);
    case State::Sweep:
      return sweep(pose);
    case State::Spin:
      return spin(pose);
    case State::Reverse:
      return reverse(pose);
    case State::Spiral:
    case State::BackUp:
    case State::Turn:
    case State::Forward:
      return vacuum(ctx, pose);
    case State::Done:
    case State::Failed:
      break;
  }
  return {};
}

// ---- the vacuum baseline ----

// xorshift32: a fixed sequence per seed, no state beyond one word.
double CoverageMission::uniform() {
  rng_ ^= rng_ << 13;
  rng_ ^= rng_ >> 17;
  rng_ ^= rng_ << 5;
  return double(rng_) / 4294967296.0;
}

bool CoverageMission::bumped(const MissionContext& ctx, const Pose2& pose) const {
  return ctx.obstacle_ahead() || lethal_near(pose, cfg_.vacuum.bump_m, true, true);
}

MissionOutput CoverageMission::vacuum(const MissionContext& ctx, const Pose2& pose) {
  const VacuumConfig& v = cfg_.vacuum;
  const double t = now_s_ - state_t0_s_;
  MissionOutput out;
  switch (state_) {
    case State::Spiral:
    case State::Forward:
      if (bumped(ctx, pose)) {
        ++bumps_;
        go(State::BackUp, "back_up");
        return out;
      }
      if (state_ == State::Spiral) {
        if (t >= v.spiral_max_s) {
          go(State::Forward, "forward");
          return out;
        }
        const double r = v.spiral_start_radius_m + v.spiral_growth_mps * t;
        out.motion.twist.vx = v.spiral_speed_mps;
        out.motion.twist.wz = v.spiral_speed_mps / r;
        return out;
      }
      if (t >= v.forward_s) {
        go(State::Spiral, "spiral");
        return out;
      }
      out.motion.twist.vx = v.forward_speed_mps;
      return out;
    case State::BackUp:
      if (t >= v.backup_s || lethal_near(pose, v.bump_m, false, true)) {
        turn_dir_ = uniform() < 0.5 ? 1.0 : -1.0;
        turn_s_ = v.turn_min_s + (v.turn_max_s - v.turn_min_s) * uniform();
        ++(turn_dir_ > 0.0 ? turns_left_ : turns_right_);
        go(State::Turn, turn_dir_ > 0.0 ? "turn_left" : "turn_right");
        return out;
      }
      out.motion.twist.vx = -v.backup_speed_mps;
      return out;
    case State::Turn:
      if (t >= turn_s_) {
        go(State::Forward, "forward");
        return out;
      }
      out.motion.twist.wz = turn_dir_ * v.turn_rate_radps;
      return out;
    default:
      return out;
  }
}

}  // namespace carril::fw
