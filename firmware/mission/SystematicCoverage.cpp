// The systematic coverage mission: its decomposition and tour, picking targets from the plans on
// the static map and the costmap, transits, sweeping the lanes, cutting a blocked lane, revisits.
// See SystematicCoverage.hpp and CoverageMission.hpp.
#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/UnsweptPatches.hpp"
#include "firmware/mission/SystematicCoverage.hpp"
#include "firmware/planning/PathWaypoints.hpp"

namespace carril::fw {

SystematicCoverage::SystematicCoverage(const CoverageConfig& cfg, const Footprint& footprint,
                                       bool holonomic, const Topic<OdometryMsg>& pose,
                                       const Topic<CostmapMsg>& costmap,
                                       const OccupancyGrid& static_map)
    : CoverageMission(cfg, footprint, pose, costmap, static_map),
      tracker_(cfg.tracker, holonomic),
      sweep_follower_(cfg.sweep),
      transit_follower_(cfg.transit_pursuit) {
  if (!init_status_ || !accounting_) return;
  const std::size_t n = area_.size();
  const int nx = static_map.nx(), ny = static_map.ny();
  abandoned_ = std::make_unique<std::uint8_t[]>(n);
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

void SystematicCoverage::restart() {
  tour_pos_ = 0;
  stops_.reset();
  if (accounting_) {
    for (std::size_t k = 0; k < area_.size(); ++k) abandoned_[k] = 0;
  }
}

MissionOutput SystematicCoverage::step(const MissionContext&, const Pose2& pose) {
  switch (state_) {
    case State::Transit:
      return transit(pose);
    case State::Sweep:
      return sweep(pose);
    case State::Spin:
      return spin(pose);
    case State::Reverse:
      return reverse(pose);
    default:
      return {};
  }
}

MissionOutput SystematicCoverage::begin(const Pose2&) {
  // Drive the tour from the end nearer the robot.
  const std::size_t n = bcd_.tour_size();
  int i = 0, j = 0;
  const Vec2 first = bcd_.entry_point(bcd_.tour()[0]);
  const Vec2 last = bcd_.exit_point(bcd_.tour()[n - 1]);
  map_.cell_of(first.x(), first.y(), i, j);
  const float to_first = planner_.cost_to_goal(i, j);
  map_.cell_of(last.x(), last.y(), i, j);
  tour_reversed_ = planner_.cost_to_goal(i, j) < to_first;
  tour_pos_ = 0;
  return next_plan(Purpose::NextCell);
}

MissionOutput SystematicCoverage::planned(const Pose2& pose) {
  switch (purpose_) {
    case Purpose::Initial:
      break;
    case Purpose::NextCell:
      if (!pick_next_cell(pose)) return next_plan(Purpose::Revisit);
      return {};
    case Purpose::Resume:
      if (!pick_resume(pose)) {
        finish_cell();
        return next_plan(Purpose::NextCell);
      }
      return {};
    case Purpose::Revisit:
      if (!pick_revisit(pose)) go(State::Done, "done");
      return {};
  }
  return {};
}

CellVisit SystematicCoverage::tour_visit(std::size_t k) const {
  const std::size_t n = bcd_.tour_size();
  if (!tour_reversed_) return bcd_.tour()[k];
  return bcd_.reversed(bcd_.tour()[n - 1 - k]);
}

// The next cell of the tour the robot can reach, entered at the corner nearest the robot by the
// planner (where the robot stands now, which a cut lane or a skipped cell moves from where the
// tour expected it).
bool SystematicCoverage::pick_next_cell(const Pose2& pose) {
  for (; tour_pos_ < bcd_.tour_size(); ++tour_pos_) {
    const CellVisit v = tour_visit(tour_pos_);
    if (swept_fraction(v.cell) >= cfg_.skip_swept_cell) {
      ++cells_done_;  // the tool already passed over it from the lanes next to it
      continue;
    }
    float best = WavefrontPlanner::kInfinity;
    int bi = 0, bj = 0;
    const std::uint8_t entries = bcd_.cell(v.cell).lanes > 1 ? 4 : 2;
    for (std::uint8_t k = 0; k < entries; ++k) {
      const CellVisit o{v.cell, k};
      const Vec2 e = bcd_.entry_point(o);
      int i = 0, j = 0;
      map_.cell_of(e.x(), e.y(), i, j);
      const float c = planner_.cost_to_goal(i, j);
      if (c < best) {
        best = c;
        visit_ = o;
        bi = i;
        bj = j;
      }
    }
    if (best >= WavefrontPlanner::kInfinity) continue;  // sealed off now: left to REVISIT
    bcd_.route(visit_, route_);  // a route too long for the buffer is swept as far as it holds
    sweep_from_ = 0;
    after_transit_ = State::Sweep;
    if (path_to(bi, bj, route_[0])) return true;
  }
  (void)pose;
  return false;
}

// The fraction of a decomposition cell's cells the tool has passed over. O(its columns * ny):
// the scans of one tick add up to the map's cells at most.
double SystematicCoverage::swept_fraction(std::uint16_t cell) const {
  const CoverCell& c = bcd_.cell(cell);
  std::size_t swept = 0;
  for (int x = c.x0; x <= c.x1; ++x) {
    for (int y = 0; y < map_.ny(); ++y) {
      if (bcd_.label(x, y) == cell && coverage_.count(x, y) > 0) ++swept;
    }
  }
  return c.area == 0 ? 1.0 : double(swept) / double(c.area);
}

bool SystematicCoverage::pick_resume(const Pose2& pose) {
  (void)pose;
  const Vec2 q = route_[sweep_from_];
  int i = 0, j = 0;
  map_.cell_of(q.x(), q.y(), i, j);
  // The lane's clear point is judged on the costmap's cells, the plan on the map's: it may fall
  // just inside an obstacle's widened disk. The nearest reachable cell within two cells does.
  int bi = -1, bj = -1, best = 9;
  for (int dj = -2; dj <= 2; ++dj) {
    for (int di = -2; di <= 2; ++di) {
      if (di * di + dj * dj >= best || !planner_.reachable(i + di, j + dj)) continue;
      best = di * di + dj * dj;
      bi = i + di;
      bj = j + dj;
    }
  }
  if (bi < 0) return false;
  after_transit_ = State::Sweep;
  return path_to(bi, bj, bi == i && bj == j ? q : map_.centre(bi, bj));
}

// The unswept cell whose anchor is nearest by the planner (each tried once). The target counts
// what the robot can reach now: unswept cells whose anchors the costmap has sealed off (an
// obstacle the map does not show stands there) are no part of it.
bool SystematicCoverage::pick_revisit(const Pose2& pose) {
  (void)pose;
  if (revisits_ >= cfg_.max_revisits) return false;
  const int nx = map_.nx();
  float best = WavefrontPlanner::kInfinity;
  std::size_t pick = 0, sealed = 0;
  std::int32_t anchor = -1;
  const std::uint8_t* coverable = area_.coverable();
  const std::uint8_t* counts = coverage_.counts();
  // Cells whose own anchor is sealed off look for another within the reach, within a budget
  // (cells looked at) that bounds this tick.
  long budget = long(area_.size());
  const double cell_m2 = map_.resolution() * map_.resolution();
  const std::uint32_t min_cells =
      std::uint32_t(std::ceil(cfg_.revisit_min_area_m2 / cell_m2 - 1e-9));
  if (min_cells > 1) {
    unswept_patch_sizes(coverable, counts, nx, map_.ny(), patch_size_.get(), patch_queue_.get());
  }
  for (std::size_t k = 0; k < area_.size(); ++k) {
    if (coverable[k] == 0 || counts[k] != 0) continue;
    if (min_cells > 1 && patch_size_[k] < min_cells) continue;
    std::int32_t a = area_.anchor(k);
    float c = planner_.cost_to_goal(int(a % nx), int(a / nx));
    if (c >= WavefrontPlanner::kInfinity && budget > 0) {
      a = reachable_anchor(k, budget);
      if (a >= 0) c = planner_.cost_to_goal(int(a % nx), int(a / nx));
    }
    if (c >= WavefrontPlanner::kInfinity) {
      ++sealed;
      continue;
    }
    if (abandoned_[k] == 0 && c < best) {
      best = c;
      pick = k;
      anchor = a;
    }
  }
  const std::size_t reachable = coverage_.mask_cells() - sealed;
  if (reachable == 0 ||
      double(coverage_.covered_cells()) >= cfg_.target_coverage * double(reachable)) {
    return false;
  }
  if (anchor < 0) return false;
  abandoned_[pick] = 1;
  ++revisits_;
  after_transit_ = State::Spin;
  const int ai = int(anchor % nx), aj = int(anchor / nx);
  spin_at_ = map_.centre(ai, aj);
  if (!path_to(ai, aj, spin_at_)) next_plan(Purpose::Revisit);
  return true;
}

// A cell the planner reached (from the robot) within the tool's reach of cell k, the nearest to
// it; -1 when none. Each cell looked at costs one from `budget`.
std::int32_t SystematicCoverage::reachable_anchor(std::size_t k, long& budget) const {
  const int nx = map_.nx();
  const int ci = int(k % std::size_t(nx)), cj = int(k / std::size_t(nx));
  const double reach = area_.reach_m() / map_.resolution();
  const int r = int(std::floor(reach));
  const double r2 = reach * reach;
  std::int32_t best = -1;
  int best_d2 = 0;
  for (int dj = -r; dj <= r; ++dj) {
    for (int di = -r; di <= r; ++di) {
      const int d2 = di * di + dj * dj;
      if (d2 > r2 || (best >= 0 && d2 >= best_d2)) continue;
      --budget;
      if (!planner_.reachable(ci + di, cj + dj)) continue;
      best = std::int32_t(cell_index(ci + di, cj + dj));
      best_d2 = d2;
    }
  }
  return best;
}

// The path from the robot (the wavefront's seed) to cell (ti, tj), ending on `target` [m].
bool SystematicCoverage::path_to(int ti, int tj, const Vec2& target) {
  if (planner_.extract_path(ti, tj, cells_) != PathResult::Ok) return false;
  std::reverse(cells_.begin(), cells_.end());
  const MapInfo& info = map_.info();
  if (!cells_to_waypoints(cells_.begin(), cells_.size(), info.origin_x_m, info.origin_y_m,
                          info.resolution_m, waypoints_)) {
    return false;
  }
  if (waypoints_.size() < 2) waypoints_.push_back(target);
  waypoints_.back() = target;
  transit_follower_.reset();
  seen_updates_ = costmap().updates();
  const Pose2 pose = pose_.get().pose;
  if ((target - Vec2(pose.x, pose.y)).norm() < cfg_.transit_pursuit.goal_tolerance_m * 2.0) {
    arrive(pose);
  } else {
    go(State::Transit, "transit");
  }
  return true;
}

void SystematicCoverage::arrive(const Pose2& pose) {
  stops_.reset();  // got there
  if (after_transit_ == State::Spin) {
    spun_rad_ = 0.0;
    spin_last_yaw_ = pose.yaw;
    go(State::Spin, "spin");
    return;
  }
  start_route_here(pose);
  join_tried_ = false;
  sweep_follower_.reset();
  go(State::Sweep, "sweep");
}

// A new cell's sweep that starts beside its route's first point (the cell may begin just beside
// where the last one ended, or a transit end within its tolerance) first drives onto it. Converging
// onto the lane while driving along it would run the first stretch off the lane, wider of it than
// the lane's clearance from a wall's end beside it. Not when the point lies behind, along the
// route: that is only a turn back.
void SystematicCoverage::start_route_here(const Pose2& pose) {
  // A resumed lane starts past what blocked it: its first point is where the lane runs clear.
  if (purpose_ != Purpose::NextCell || sweep_from_ + 1 >= route_.size()) return;
  const Vec2 here(pose.x, pose.y), first = route_[sweep_from_];
  const Vec2 to = first - here;
  const double d = to.norm();
  if (d < kOnRouteM) return;
  const Vec2 along = route_[sweep_from_ + 1] - first;
  if (to.dot(along) < -0.5 * d * along.norm()) return;
  // A new cell's route starts at its beginning (sweep_from_ 0): the robot goes in front of it.
  if (!route_.try_push_back(route_.back())) return;  // no room: converge as before
  for (std::size_t k = route_.size() - 2; k > 0; --k) route_[k] = route_[k - 1];
  route_[0] = here;
}

void SystematicCoverage::finish_cell() {
  lanes_ += bcd_.cell(visit_.cell).lanes;
  ++cells_done_;
  ++tour_pos_;
}

// On the last lane of a cell: when the tour's next cell begins with a lane across from this
// one's end, at the same end and driven the other way (the sweep goes on from one cell into the
// next, as at a door's jamb or a wall's end that split them), the route turns into it by a U-turn
// as the lanes' own, instead of ending at the wall for a plan, a transit and two turns on the
// spot. Only where the turn's centre line stays on cells the centre may stand on and clear of
// what the costmap shows, and is still ahead of the robot. The finished cell is counted done and
// the next one becomes the visit.
bool SystematicCoverage::join_next_cell(const Pose2& pose) {
  const std::size_t n = route_.size();
  if (cfg_.join_max_gap_m <= 0.0 || n < sweep_from_ + 2 || bcd_.cell(visit_.cell).single_pass ||
      tour_pos_ + 1 >= bcd_.tour_size()) {
    return false;
  }
  const Vec2 a = route_[n - 2], b = route_[n - 1];
  if (a.x() != b.x() || a.y() == b.y()) return false;  // the last lane, along the sweep line
  const bool up = b.y() > a.y();
  const CellVisit next = tour_visit(tour_pos_ + 1);
  const CoverCell& c = bcd_.cell(next.cell);
  if (c.single_pass || swept_fraction(next.cell) >= cfg_.skip_swept_cell) return false;
  const double res = map_.resolution();
  bool found = false;
  CellVisit o{};
  Vec2 e(0.0, 0.0);
  const std::uint8_t entries = c.lanes > 1 ? 4 : 2;
  for (std::uint8_t k = 0; k < entries; ++k) {
    if (((k & 1) != 0) != up) continue;  // starts at this lane's end, driven the other way
    const CellVisit v{next.cell, k};
    const Vec2 p = bcd_.entry_point(v);
    const double dx = std::fabs(p.x() - b.x());
    if (dx < res || dx > cfg_.join_max_gap_m || std::fabs(p.y() - b.y()) > cfg_.join_max_step_m) {
      continue;
    }
    if (!found || dx < std::fabs(e.x() - b.x())) {
      found = true;
      o = v;
      e = p;
    }
  }
  if (!found) return false;
  const double end_y = up ? std::min(b.y(), e.y()) : std::max(b.y(), e.y());
  const double vy = up ? 1.0 : -1.0;
  route_.pop_back();
  const std::size_t turn_from = route_.size();
  // The turn reaches end_y; this lane's start bounds its radius (the next one's is checked below).
  const bool laid = bcd_.u_turn(a.x(), e.x(), up, up ? end_y : a.y(), up ? a.y() : end_y, route_) &&
                    route_.size() > turn_from;
  const std::size_t next_from = route_.size();
  bool ok = laid && bcd_.append_route(o, route_) && route_.size() >= next_from + 2;
  if (ok) {
    // Where the turn leaves this lane is ahead of the robot (by a braking distance's margin),
    // and its second lane runs on past where the turn meets it.
    const double leave = route_[turn_from].y(), meet = route_[next_from - 1].y();
    // A lane that turns again sooner than kJoinSettleM past the meeting point would enter that
    // turn still settling from this one, wide of it.
    const double run = vy * (meet - route_[next_from + 1].y());
    ok = vy * (leave - pose.y) > 0.05 && vy * (leave - a.y()) >= 0.0 && run > 0.0 &&
         (run >= kJoinSettleM || route_.size() == next_from + 2);
  }
  if (ok) {
    // The next route's entry point lies on its first lane at or beyond where the turn meets it.
    for (std::size_t k = next_from; k + 1 < route_.size(); ++k) route_[k] = route_[k + 1];
    route_.pop_back();
    ok = join_clear(turn_from, next_from - 1);
  }
  if (!ok) {
    route_.truncate(turn_from);
    route_.push_back(b);
    return false;
  }
  finish_cell();
  visit_ = o;
  ++joins_;
  return true;
}

// Whether the route's centre line from point `from` to point `to` stays on cells where the
// robot's centre may stand, clear of obstacles the map does not show.
bool SystematicCoverage::join_clear(std::size_t from, std::size_t to) const {
  const double step = 0.5 * map_.resolution();
  for (std::size_t i = from; i < to; ++i) {
    const Vec2 a = route_[i], b = route_[i + 1];
    const int m = std::max(1, int(std::ceil((b - a).norm() / step)));
    for (int k = 0; k <= m; ++k) {
      const Vec2 p = a + (b - a) * (double(k) / m);
      int ci = 0, cj = 0;
      if (!map_.cell_of(p.x(), p.y(), ci, cj)) return false;
      if (base_costs_[cell_index(ci, cj)] == cost::kLethal || blocked_at(p)) return false;
    }
  }
  return true;
}

MissionOutput SystematicCoverage::transit(const Pose2& pose) {
  if (costmap().updates() != seen_updates_) {
    seen_updates_ = costmap().updates();
    if (path_blocked_ahead(pose)) {
      ++replans_;
      return start_plan(purpose_, pose);
    }
  }
  MissionOutput out;
  out.motion.twist = transit_follower_.update(pose, waypoints_.begin(), waypoints_.size());
  Twist& t = out.motion.twist;
  if (t.vx > cfg_.speed_mps) {
    // Faster than the lanes only in the open: near the edge of where the centre may stand (at a
    // door's jamb, along a wall), here or just ahead, the pursuit's cut corners would touch.
    const Vec2 here(pose.x, pose.y);
    const Vec2 ahead =
        here + cfg_.transit_edge_lookahead_m * Vec2(std::cos(pose.yaw), std::sin(pose.yaw));
    if (near_edge(here) || near_edge(ahead)) {
      t.wz *= cfg_.speed_mps / t.vx;  // the same curvature
      t.vx = cfg_.speed_mps;
    }
  }
  if (out.motion.twist.vx > 0.0 && lethal_near(pose, cfg_.emergency_stop_m, true, false)) {
    if (std::fabs(out.motion.twist.wz) >= cfg_.turn_in_place_min_radps) {
      out.motion.twist.vx = 0.0;
      return out;
    }
    return emergency_stop(pose);
  }
  if (transit_follower_.at_end()) arrive(pose);
  return out;
}

// Whether a cell within transit_edge_margin_m of p is no place for the robot's centre (the
// static area's edge: a wall or a jamb within the inscribed radius plus that margin).
bool SystematicCoverage::near_edge(const Vec2& p) const {
  int ci = 0, cj = 0;
  if (!map_.cell_of(p.x(), p.y(), ci, cj)) return true;
  const int r = int(std::ceil(cfg_.transit_edge_margin_m / map_.resolution()));
  for (int dj = -r; dj <= r; ++dj) {
    for (int di = -r; di <= r; ++di) {
      if (di * di + dj * dj > r * r) continue;
      if (!map_.contains(ci + di, cj + dj)) return true;
      if (base_costs_[cell_index(ci + di, cj + dj)] == cost::kLethal) return true;
    }
  }
  return false;
}

// Stop, back off, plan again; after max_recoveries stops in a row the target is given up.
MissionOutput SystematicCoverage::emergency_stop(const Pose2& pose) {
  const Vec2 here(pose.x, pose.y);
  if (stops_.too_many(here, 2.0 * cfg_.backup_m, cfg_.max_recoveries)) {
    stops_.reset();
    if (purpose_ == Purpose::Revisit) return next_plan(Purpose::Revisit);
    finish_cell();
    return next_plan(Purpose::NextCell);
  }
  backup_from_ = here;
  go(State::Reverse, "reverse");
  return {};
}

MissionOutput SystematicCoverage::reverse(const Pose2& pose) {
  const bool far_enough = (Vec2(pose.x, pose.y) - backup_from_).norm() >= cfg_.backup_m;
  if (far_enough || lethal_near(pose, cfg_.emergency_stop_m, false, false)) {
    ++replans_;
    return next_plan(purpose_);
  }
  MissionOutput out;
  out.motion.twist.vx = -cfg_.backup_speed_mps;
  return out;
}

MissionOutput SystematicCoverage::sweep(const Pose2& pose) {
  // On the route's last lane: join the next cell to it where a U-turn leads into it (once per
  // last lane; a joined cell's own last lane is looked at in turn).
  if (!join_tried_ && sweep_from_ + sweep_follower_.progress() + 2 >= route_.size()) {
    join_tried_ = !join_next_cell(pose);
  }
  const Vec2* path = route_.begin() + sweep_from_;
  const std::size_t n = route_.size() - sweep_from_;
  MissionOutput out;
  // An obstacle the map does not show on the lane ahead: cut the lane there.
  const Vec2 here(pose.x, pose.y);
  const PathProjection at = project_on_path(path, n, here, sweep_follower_.progress(), 2);
  const double step = 0.5 * map_.resolution();
  for (double s = step; s <= cfg_.block_lookahead_m; s += step) {
    const Vec2 p = point_ahead(path, n, at, s);
    if ((p - here).norm() > footprint_.half_width_m && blocked_at(p)) {
      if (cut_lane(pose, at)) return start_plan(Purpose::Resume, pose);
      finish_cell();
      return start_plan(Purpose::NextCell, pose);
    }
  }
  out.motion.twist = sweep_follower_.update(pose, path, n);
  if (out.motion.twist.vx > 0.0 && lethal_near(pose, cfg_.emergency_stop_m, true, false)) {
    if (std::fabs(out.motion.twist.wz) >= cfg_.turn_in_place_min_radps) {
      out.motion.twist.vx = 0.0;
      return out;
    }
    // Something touches the front the lane check missed: back off, then resume past it.
    const bool resumes = cut_lane(pose, at);
    if (!resumes) finish_cell();
    purpose_ = resumes ? Purpose::Resume : Purpose::NextCell;
    return emergency_stop(pose);
  }
  if (sweep_follower_.at_end()) {
    finish_cell();
    return next_plan(Purpose::NextCell);
  }
  return out;
}

// Past the blocked stretch ahead of projection `at`, the first point from which the lane runs
// clear for resume_clear_m becomes the route's start (route_[k] moved onto it, k its segment).
// false when the rest of the route is blocked.
bool SystematicCoverage::cut_lane(const Pose2& pose, const PathProjection& at) {
  (void)pose;
  ++lanes_blocked_;
  const double step = 0.5 * map_.resolution();
  bool seen_block = false;
  double clear_from = -1.0;
  std::size_t seg = 0;
  Vec2 q(0.0, 0.0);
  double s = 0.0;
  Vec2 a = at.point;
  for (std::size_t i = sweep_from_ + at.segment + 1; i < route_.size(); ++i) {
    const Vec2 b = route_[i];
    const double len = (b - a).norm();
    const int n = std::max(1, int(std::ceil(len / step)));
    for (int k = 1; k <= n; ++k) {
      const Vec2 p = a + (b - a) * (double(k) / n);
      const double sp = s + len * k / n;
      if (blocked_at(p)) {
        seen_block = true;
        clear_from = -1.0;
        continue;
      }
      if (!seen_block) continue;
      if (clear_from < 0.0) {
        clear_from = sp;
        seg = i - 1;
        q = p;
      }
      if (sp - clear_from >= cfg_.resume_clear_m) {
        route_[seg] = q;
        sweep_from_ = seg;
        return true;
      }
    }
    s += len;
    a = b;
  }
  if (seen_block && clear_from >= 0.0) {  // clear to the end, though shorter than resume_clear_m
    route_[seg] = q;
    sweep_from_ = seg;
    return true;
  }
  return false;
}

MissionOutput SystematicCoverage::spin(const Pose2& pose) {
  spun_rad_ += std::fabs(wrap_angle(pose.yaw - spin_last_yaw_));
  spin_last_yaw_ = pose.yaw;
  if (spun_rad_ >= cfg_.revisit_spin_rad) {
    // What the turn did not reach round here is out of the tool's reach from where the robot
    // can stand: not tried again.
    const double res = map_.resolution();
    const int r = int(std::ceil(cfg_.tool_width_m / res));
    int ci = 0, cj = 0;
    map_.cell_of(spin_at_.x(), spin_at_.y(), ci, cj);
    for (int j = cj - r; j <= cj + r; ++j) {
      for (int i = ci - r; i <= ci + r; ++i) {
        if (!map_.contains(i, j) || coverage_.count(i, j) != 0) continue;
        if ((map_.centre(i, j) - spin_at_).norm() <= cfg_.tool_width_m) {
          abandoned_[cell_index(i, j)] = 1;
        }
      }
    }
    return next_plan(Purpose::Revisit);
  }
  MissionOutput out;
  out.motion.twist.wz = cfg_.spin_rate_radps;
  return out;
}

bool SystematicCoverage::path_blocked_ahead(const Pose2& pose) const {
  return fw::path_blocked_ahead(pose, waypoints_.begin(), waypoints_.size(),
                                transit_follower_.progress() + 1, cfg_.replan_lookahead_m,
                                0.5 * map_.resolution(), footprint_.half_width_m,
                                [&](const Vec2& p) { return blocked_at(p); });
}

}  // namespace carril::fw
