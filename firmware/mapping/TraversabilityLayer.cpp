#include "firmware/mapping/TraversabilityLayer.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/core/Geometry.hpp"
#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

Status TraversabilityProfile::validate() const {
  return Checks("traversability")
      .range("max_slope_deg", max_slope_deg, 0.1, 89.0, "deg")
      .range("max_step_up_m", max_step_up_m, 0.001, 5.0, "m")
      .range("max_step_down_m", max_step_down_m, 0.001, 5.0, "m")
      .range("graded_cost_max", double(graded_cost_max), 1.0, double(cost::kMaxGraded), "")
      .result();
}

Status TraversabilityLayer::init(int nx, int ny, double resolution_m) {
  if (!grid_.init(nx, ny, resolution_m, cost::kUnknown))
    return Status::error("traversability: grid %d x %d cells at %g m, expected positive sizes", nx,
                         ny, resolution_m);
  return Status::ok();
}

void TraversabilityLayer::mark_start_free(double x, double y, double radius_m) {
  if (!std::isfinite(x) || !std::isfinite(y) || !(radius_m > 0.0) || !std::isfinite(radius_m))
    return;
  start_set_ = true;
  start_x_ = x;
  start_y_ = y;
  start_r2_ = radius_m * radius_m;
  for (int ly = 0; ly < grid_.ny(); ++ly)
    for (int lx = 0; lx < grid_.nx(); ++lx) {
      std::uint8_t& c = grid_.local(lx, ly);
      if (c == cost::kUnknown && in_start_area(grid_.origin_cx() + lx, grid_.origin_cy() + ly))
        c = cost::kFree;
    }
}

bool TraversabilityLayer::in_start_area(int cx, int cy) const {
  if (!start_set_) return false;
  const double dx = grid_.center_of(cx) - start_x_, dy = grid_.center_of(cy) - start_y_;
  return dx * dx + dy * dy <= start_r2_;
}

std::uint8_t TraversabilityLayer::classify(TerrainStatus status, float slope_rad, float step_up_m,
                                           float step_down_m, float drop_m,
                                           const TraversabilityProfile& p) {
  if (status == TerrainStatus::kUnobserved) return cost::kUnknown;
  // Steps are known even where a plane is not (a cell next to a wall face).
  const double up = double(step_up_m) / p.max_step_up_m;
  const double down = double(std::max(step_down_m, drop_m)) / p.max_step_down_m;
  if (up > 1.0 || down > 1.0) return cost::kLethal;
  if (status != TerrainStatus::kValid) return cost::kUnknown;
  const double slope = double(slope_rad) / (p.max_slope_deg * kPi / 180.0);
  if (slope > 1.0) return cost::kLethal;
  const double worst = std::max({slope, up, down, 0.0});
  return std::uint8_t(std::lround(worst * p.graded_cost_max));
}

void TraversabilityLayer::update(const TerrainAnalysis& t, const TraversabilityProfile& p) {
  if (t.nx() != grid_.nx() || t.ny() != grid_.ny()) return;
  grid_.move_origin(t.origin_cx(), t.origin_cy());
  const TerrainStatus* st = t.status();
  const float *slope = t.slope_rad(), *up = t.step_up_m(), *down = t.step_down_m(),
              *drop = t.drop_m();
  for (int ly = t.rect_y0(); ly < t.rect_y0() + t.rect_h(); ++ly) {
    std::uint8_t* row = grid_.storage_row(ly);
    const int off = grid_.column_offset();
    for (int lx = t.rect_x0(); lx < t.rect_x0() + t.rect_w(); ++lx) {
      const std::size_t i = t.index(lx, ly);
      std::uint8_t c = classify(st[i], slope[i], up[i], down[i], drop[i], p);
      if (c == cost::kUnknown && st[i] != TerrainStatus::kValid &&
          in_start_area(grid_.origin_cx() + lx, grid_.origin_cy() + ly))
        c = cost::kFree;
      row[(off + lx) % grid_.nx()] = c;
    }
  }
}

}  // namespace carril::fw
