#include "firmware/mapping/ObstacleLayer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/GridRay.hpp"

namespace carril::fw {

namespace {
// Scan values are classified by their bits before any arithmetic: a signalling NaN from a corrupt
// frame would trap on its first comparison or float-to-double conversion.
constexpr std::uint32_t kExpMask = 0x7F800000U, kSignBit = 0x80000000U;
bool finite_bits(float f) {
  return (std::bit_cast<std::uint32_t>(f) & kExpMask) != kExpMask;
}
bool is_plus_inf(float f) {
  return std::bit_cast<std::uint32_t>(f) == kExpMask;
}
bool is_negative(float f) {
  return (std::bit_cast<std::uint32_t>(f) & kSignBit) != 0;
}
}  // namespace

Status ObstacleLayerConfig::validate() const {
  return Checks("costmap.obstacle")
      .range("obstacle_max_range_m", obstacle_max_range_m, 0.1, 100.0, "m")
      .range("raytrace_max_range_m", raytrace_max_range_m, 0.1, 100.0, "m")
      .range("raytrace_min_range_m", raytrace_min_range_m, 0.0, 100.0, "m")
      .fail_if(!(raytrace_min_range_m < raytrace_max_range_m), "raytrace_min_range_m",
               "must be below raytrace_max_range_m")
      .range("clear_scans", clear_scans, 1, 200, "scans")
      .range("decay_s", decay_s, 0.0, 3000.0, "s")
      .result();
}

bool ObstacleLayer::init(const ObstacleLayerConfig& cfg, int nx, int ny, double resolution_m) {
  cfg_ = cfg;
  scan_counter_ = 0;
  decayed_once_ = false;
  start_ = RayStart{};
  return cost_.init(nx, ny, resolution_m, cost::kUnknown) &&
         state_.init(nx, ny, resolution_m, CellState{});
}

void ObstacleLayer::recenter(double x, double y) {
  cost_.recenter(x, y);
  state_.recenter(x, y);
}

void ObstacleLayer::clear() {
  cost_.clear();
  state_.clear();
}

// Clears the cells from (x0, y0) to (x1, y1) [m], without the end cell when keep_end (it holds
// the return that ended the beam). Counts at most one miss per lethal cell and scan.
// (col_off, row_off) is the storage position of the window's first cell, found once per scan
// rather than with two divisions per ray.
void ObstacleLayer::clear_ray(double x0, double y0, double x1, double y1, bool keep_end,
                              int col_off, int row_off) {
  const double res = cost_.resolution();
  const int nx = cost_.nx(), ny = cost_.ny();
  // The window box, shrunk by a hair so that floor() of a clipped point stays inside.
  const double eps = 1e-6 * res;
  bool end_clipped = false;
  if (!grid::clip_segment(x0, y0, x1, y1, cost_.origin_x(), cost_.origin_y(),
                          cost_.origin_x() + nx * res - eps, cost_.origin_y() + ny * res - eps,
                          end_clipped)) {
    return;
  }
  const int lo_x = cost_.origin_cx(), lo_y = cost_.origin_cy();
  // The rays of a scan start at the same point (the sensor, with no minimum range): its cell is
  // worked out once, not with two divisions per ray.
  if (x0 != start_.x || y0 != start_.y || lo_x != start_.lo_x || lo_y != start_.lo_y) {
    start_ = RayStart{x0,
                      y0,
                      lo_x,
                      lo_y,
                      std::clamp(cost_.cell_of(x0), lo_x, lo_x + nx - 1),
                      std::clamp(cost_.cell_of(y0), lo_y, lo_y + ny - 1)};
  }
  const int cx0 = start_.cx, cy0 = start_.cy;
  const int cx1 = std::clamp(cost_.cell_of(x1), lo_x, lo_x + nx - 1);
  const int cy1 = std::clamp(cost_.cell_of(y1), lo_y, lo_y + ny - 1);
  const bool include_end = end_clipped || !keep_end;
  // The same cells as the last ray of this scan: its walk already cleared them, and counted
  // this scan's miss on each lethal one (last_miss), so walking them again would change nothing.
  const LastRay ray{cx0, cy0, cx1, cy1, include_end, true};
  if (ray == last_ray_) return;  // equal only to a valid one
  last_ray_ = ray;
  std::uint8_t* cost = grid::storage_base(cost_);
  CellState* state = grid::storage_base(state_);
  const std::uint8_t scan = scan_counter_;
  // The start cell lies in the window.
  const int col0 = grid::window_storage(cx0, lo_x, col_off, nx);
  const int row0 = grid::window_storage(cy0, lo_y, row_off, ny);
  const int skip = cx0 == free_cx_ && cy0 == free_cy_ ? free_skip_ : 0;
  grid::trace_line_from(
      col0, row0, cx1 - cx0, cy1 - cy0, nx, ny, include_end,
      [&](std::size_t i) {
        // Most cells on a ray are free already: a load and a compare, no store (a store would
        // dirty every cache line the fan crosses). Lethal cells are rare.
        const std::uint8_t v = cost[i];
        if (v == cost::kFree) [[likely]]
          return;
        if (v != cost::kLethal) {
          cost[i] = cost::kFree;
          return;
        }
        CellState& s = state[i];
        if (s.last_miss == scan) return;  // already counted in this scan
        s.last_miss = scan;
        if (s.misses_left > 0) --s.misses_left;
        if (s.misses_left == 0) cost[i] = cost::kFree;
      },
      skip);
}

int ObstacleLayer::free_radius(int cx, int cy, int r_cap) const {
  const int nx = cost_.nx(), ny = cost_.ny(), lo_x = cost_.origin_cx(), lo_y = cost_.origin_cy();
  if (!cost_.contains(cx, cy)) return -1;
  // No ring past the window's nearest edge.
  r_cap = std::min({r_cap, cx - lo_x, lo_x + nx - 1 - cx, cy - lo_y, lo_y + ny - 1 - cy});
  const std::uint8_t* cost = grid::storage_base(cost_);
  // Storage column and row of global cell (x, y) (see grid::storage_index).
  const auto col_of = [nx](int x) { return grid::wrap(x, nx); };
  const auto row_of = [ny](int y) { return grid::wrap(y, ny); };
  // Cells x0..x0+len-1 of row y all free (the span may wrap round the storage row once).
  const auto row_free = [&](int x0, int len, int y) {
    const std::uint8_t* row = cost + std::size_t(row_of(y)) * std::size_t(nx);
    const int c0 = col_of(x0), first = std::min(len, nx - c0);
    std::uint8_t any = 0;
    for (int k = 0; k < first; ++k) any |= row[c0 + k];
    for (int k = 0; k < len - first; ++k) any |= row[k];
    static_assert(cost::kFree == 0, "a span is free when its OR is 0");
    return any == 0;
  };
  // Cells y0..y0+len-1 of column x all free.
  const auto column_free = [&](int x, int y0, int len) {
    const std::uint8_t* col = cost + col_of(x);
    int r = row_of(y0);
    std::uint8_t any = 0;
    for (int k = 0; k < len; ++k) {
      any |= col[std::size_t(r) * std::size_t(nx)];
      if (++r == ny) r = 0;
    }
    return any == 0;
  };
  if (!row_free(cx, 1, cy)) return -1;
  int r = 1;
  for (; r <= r_cap; ++r) {
    // Ring r: the rows r above and below (2r + 1 cells each), then the columns between them.
    if (!row_free(cx - r, 2 * r + 1, cy - r) || !row_free(cx - r, 2 * r + 1, cy + r) ||
        !column_free(cx - r, cy - r + 1, 2 * r - 1) ||
        !column_free(cx + r, cy - r + 1, 2 * r - 1)) {
      break;
    }
  }
  return r - 1;
}

ObstacleUpdateStats ObstacleLayer::update(const hal::LaserScan& scan, const Pose2& sensor_pose) {
  ObstacleUpdateStats st;
  const int n = std::min<int>(scan.count, hal::kMaxScanBeams);
  free_skip_ = 0;  // until this scan's free square is known
  if (!cost_.ready() || !std::isfinite(sensor_pose.x) || !std::isfinite(sensor_pose.y) ||
      !std::isfinite(sensor_pose.yaw) || !finite_bits(scan.angle_min_rad) ||
      !finite_bits(scan.angle_increment_rad)) {
    st.ignored = n;
    return st;
  }
  ++scan_counter_;
  last_ray_ = LastRay{};  // a new scan counts its own misses, on every ray
  beams_.update(scan);
  const double yaw_c = std::cos(sensor_pose.yaw), yaw_s = std::sin(sensor_pose.yaw);
  const std::uint16_t now_ds = std::uint16_t((scan.stamp_ns / 100'000'000) & 0xFFFF);
  // A return is a measurement only between the sensor's limits; with no limits given, any
  // positive range is.
  const double range_min = finite_bits(scan.range_min_m) ? double(scan.range_min_m) : 0.0;
  const double range_max = finite_bits(scan.range_max_m) && scan.range_max_m > 0.0F
                               ? double(scan.range_max_m)
                               : HUGE_VAL;
  // "Nothing within range_max" (+inf, or beyond range_max) clears to the clearing range, but no
  // farther than the sensor could see.
  const double free_to = std::min(cfg_.raytrace_max_range_m, range_max);
  const double rmin = cfg_.raytrace_min_range_m;
  const int col_off = cost_.column_offset(), row_off = cost_.row_offset();
  const int nx = cost_.nx(), ny = cost_.ny();
  // Rays from the sensor (no minimum range) start in its cell; the cells round it that are free
  // now need no walk. Rays never walk farther than the clearing range.
  if (rmin == 0.0 && !walk_every_cell_ &&
      cost_.world_to_cell(sensor_pose.x, sensor_pose.y, free_cx_, free_cy_)) {
    const int r_cap = int(std::ceil(cfg_.raytrace_max_range_m / cost_.resolution())) + 1;
    free_skip_ = free_radius(free_cx_, free_cy_, r_cap) + 1;
  }
  int n_hits = 0;
  for (int b = 0; b < n; ++b) {
    const float rf = scan.ranges_m[std::size_t(b)];
    // NaN, -inf, 0 and negatives say nothing about free space; +inf says "nothing in range".
    const bool inf = is_plus_inf(rf);
    if (!inf && (!finite_bits(rf) || is_negative(rf) || rf == 0.0F || double(rf) < range_min)) {
      ++st.ignored;
      continue;
    }
    const double r = inf ? HUGE_VAL : double(rf);
    double c = 0.0, s = 0.0;
    beams_.rotate(b, yaw_c, yaw_s, c, s);
    const bool is_return = !inf && r <= range_max;
    const double end = is_return ? std::min(r, cfg_.raytrace_max_range_m) : free_to;
    // The return's own cell is kept when the ray reaches it.
    const bool keep_end = is_return && r <= cfg_.raytrace_max_range_m;
    if (end > rmin) {
      clear_ray(sensor_pose.x + rmin * c, sensor_pose.y + rmin * s, sensor_pose.x + end * c,
                sensor_pose.y + end * s, keep_end, col_off, row_off);
    }
    if (is_return && r <= cfg_.obstacle_max_range_m) {
      int cx = 0, cy = 0;
      if (cost_.world_to_cell(sensor_pose.x + r * c, sensor_pose.y + r * s, cx, cy)) {
        // Its storage cell (the cell is in the window).
        const int col = grid::window_storage(cx, cost_.origin_cx(), col_off, nx);
        const int row = grid::window_storage(cy, cost_.origin_cy(), row_off, ny);
        hits_[std::size_t(n_hits)] = std::size_t(row) * std::size_t(nx) + std::size_t(col);
        ++n_hits;
      }
      ++st.marked;
    } else {
      ++st.cleared;
    }
  }
  // Marking after all the clearing: a cell hit by one beam and crossed by a neighbour (a wall
  // seen at a grazing angle) stays lethal, and its miss count is re-armed.
  const auto clear_scans = std::uint8_t(cfg_.clear_scans);
  std::uint8_t* cost = grid::storage_base(cost_);
  CellState* state = grid::storage_base(state_);
  for (int h = 0; h < n_hits; ++h) {
    const std::size_t i = hits_[std::size_t(h)];
    cost[i] = cost::kLethal;
    CellState& s = state[i];
    s.misses_left = clear_scans;
    s.last_miss = scan_counter_;
    s.hit_time_ds = now_ds;
  }
  if (cfg_.decay_s > 0.0 && (!decayed_once_ || now_ds != last_decay_ds_)) decay(now_ds);
  return st;
}

// Lethal cells whose last hit is decay_s old become unknown: nothing has confirmed them since.
void ObstacleLayer::decay(std::uint16_t now_ds) {
  decayed_once_ = true;
  last_decay_ds_ = now_ds;
  const auto max_age = std::uint16_t(std::lround(cfg_.decay_s * 10.0));
  std::uint8_t* cost = grid::storage_base(cost_);
  const CellState* state = grid::storage_base(state_);
  const std::size_t n = std::size_t(cost_.nx()) * std::size_t(cost_.ny());
  for (std::size_t i = 0; i < n; ++i) {
    if (cost[i] == cost::kLethal && std::uint16_t(now_ds - state[i].hit_time_ds) >= max_age) {
      cost[i] = cost::kUnknown;
    }
  }
}

}  // namespace carril::fw
