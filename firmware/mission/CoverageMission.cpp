// What the coverage missions share: configuration, the area's construction, the frame of every
// tick, the reachable area's plan, and make_coverage_mission(). The missions are
// SystematicCoverage.cpp and VacuumCoverage.cpp.
#include "firmware/mission/CoverageMission.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/MissionStates.hpp"
#include "firmware/mission/SystematicCoverage.hpp"
#include "firmware/mission/VacuumCoverage.hpp"

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
                                 const Topic<OdometryMsg>& pose, const Topic<CostmapMsg>& costmap,
                                 const OccupancyGrid& static_map)
    : cfg_(cfg),
      footprint_(footprint),
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
  mapped_ = std::make_unique<std::uint8_t[]>(n);
  build_mapped_mask();
  accounting_ = true;
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
  cells_done_ = lanes_ = lanes_blocked_ = revisits_ = bumps_ = replans_ = joins_ = 0;
  turns_left_ = turns_right_ = 0;
  fault_ = Fault::None;
  if (accounting_) coverage_.clear();
  restart();
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
      return begin(pose);
    case State::Plan:
      return plan_step(pose);
    case State::Done:
    case State::Failed:
      break;
    default:
      return step(ctx, pose);
  }
  return {};
}

namespace {
const char* plan_phase(int purpose) {
  static const char* const kNames[] = {"plan", "next_cell", "resume", "revisit"};
  return kNames[purpose];
}
}  // namespace

MissionOutput CoverageMission::next_plan(Purpose p) {
  purpose_ = p;
  planning_ = false;
  go(State::Plan, plan_phase(int(p)));
  return {};
}

MissionOutput CoverageMission::start_plan(Purpose p, const Pose2& pose) {
  next_plan(p);
  return plan_step(pose);
}

// One PLAN tick. The first lays the obstacles the map does not show over the static area (the
// initial plan: the static area alone, so a passing obstacle does not shrink the area for good)
// and seeds a wavefront at the robot; the next ones expand it within the budget; the last picks
// the target from its distances and extracts the path.
MissionOutput CoverageMission::plan_step(const Pose2& pose) {
  const int nx = map_.nx(), ny = map_.ny();
  if (!planning_) {
    const std::size_t n = area_.size();
    for (std::size_t k = 0; k < n; ++k) plan_costs_[k] = base_costs_[k];
    if (purpose_ != Purpose::Initial) overlay_unmapped();
    // The robot's cell, or (standing in inflation) the nearest passable one within 0.3 m.
    int ri = 0, rj = 0;
    map_.cell_of(pose.x, pose.y, ri, rj);
    const int r = std::max(1, int(std::ceil(0.3 / map_.resolution())));
    int si = -1, sj = -1, best = r * r + 1;
    for (int dj = -r; dj <= r; ++dj) {
      for (int di = -r; di <= r; ++di) {
        const int i = ri + di, j = rj + dj;
        if (!map_.contains(i, j) || di * di + dj * dj >= best) continue;
        if (!cost::passable(plan_costs_[cell_index(i, j)])) continue;
        best = di * di + dj * dj;
        si = i;
        sj = j;
      }
    }
    if (si < 0 || planner_.start(plan_costs_.get(), nx, ny, si, sj) != WavefrontStatus::Running) {
      return fail(Fault::NoPath);
    }
    planning_ = true;
    return {};  // laying the costs and seeding are this tick's work
  }
  if (planner_.step(cfg_.plan_expansions_per_tick) == WavefrontStatus::Running) return {};
  planning_ = false;
  if (purpose_ == Purpose::Initial) {
    // The area the robot can reach; what is sealed off is no part of the job.
    area_.keep_anchored([&](std::size_t a) {
      return planner_.reachable(int(a % std::size_t(nx)), int(a / std::size_t(nx)));
    });
    coverage_.set_mask(area_.coverable());
    if (area_.coverable_cells() == 0) return fail(Fault::NoPath);
    return begin(pose);
  }
  return planned(pose);
}

std::unique_ptr<CoverageMission> make_coverage_mission(const CoverageConfig& cfg,
                                                       const Footprint& footprint, bool holonomic,
                                                       const Topic<OdometryMsg>& pose,
                                                       const Topic<CostmapMsg>& costmap,
                                                       const OccupancyGrid& static_map) {
  if (cfg.mode == CoverageMode::Vacuum) {
    return std::make_unique<VacuumCoverage>(cfg, footprint, pose, costmap, static_map);
  }
  return std::make_unique<SystematicCoverage>(cfg, footprint, holonomic, pose, costmap, static_map);
}

}  // namespace carril::fw
