#include "firmware/mapping/LayeredCostmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/GridRay.hpp"

namespace carril::fw {

namespace {
// The largest window init() accepts [cells per side] (a 25 m window at 5 cm).
constexpr int kMaxCellsPerSide = 500;
}  // namespace

int CostmapConfig::nx() const {
  return int(std::lround(size_x_m / resolution_m));
}
int CostmapConfig::ny() const {
  return int(std::lround(size_y_m / resolution_m));
}

Status CostmapConfig::validate() const {
  Checks c("costmap");
  c.range("resolution_m", resolution_m, 0.005, 1.0, "m")
      .range("size_x_m", size_x_m, 0.5, 200.0, "m")
      .range("size_y_m", size_y_m, 0.5, 200.0, "m");
  if (!c.result().is_ok()) return c.result();
  return c.range("size_x_m / resolution_m", double(nx()), 4.0, double(kMaxCellsPerSide), "cells")
      .range("size_y_m / resolution_m", double(ny()), 4.0, double(kMaxCellsPerSide), "cells")
      .nested(obstacle.validate())
      .nested(inflation.validate())
      .range("inflation.inflation_radius_m / resolution_m",
             inflation.inflation_radius_m / resolution_m, 0.0,
             double(InflationLayer::kMaxRadiusCells), "cells")
      .result();
}

Status LayeredCostmap::init(const CostmapConfig& cfg) {
  const Status s = cfg.validate();
  if (!s.is_ok()) return s;
  cfg_ = cfg;
  const int nx = cfg.nx(), ny = cfg.ny();
  if (!master_.init(nx, ny, cfg.resolution_m, cost::kUnknown) ||
      !obstacles_.init(cfg.obstacle, nx, ny, cfg.resolution_m) ||
      !inflation_.init(cfg.inflation, nx, ny, cfg.resolution_m)) {
    return Status::error("costmap: grid allocation failed for %d x %d cells", nx, ny);
  }
  return Status::ok();
}

void LayeredCostmap::recenter(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  master_.recenter(x, y);
  obstacles_.recenter(x, y);
}

bool LayeredCostmap::update_master(const RollingGrid<std::uint8_t>* const extra_layers[], int n) {
  // Shifting every cost by +1 (mod 256) maps unknown 255 to 0, below every known cost, and lethal
  // 254 to 255, above all: then one max per cell implements the combination rule.
  const std::size_t cells = std::size_t(master_.nx()) * std::size_t(master_.ny());
  std::uint8_t* m = grid::storage_base(master_);
  const std::uint8_t* obs = grid::storage_base(obstacles_.grid());
  for (std::size_t i = 0; i < cells; ++i) m[i] = std::uint8_t(obs[i] + 1);
  bool all_used = true;
  for (int k = 0; k < n; ++k) {
    const RollingGrid<std::uint8_t>* layer = extra_layers[k];
    if (layer == nullptr || !layer->ready() || !grid::same_window(*layer, master_)) {
      all_used = false;
      continue;
    }
    const std::uint8_t* e = grid::storage_base(*layer);
    for (std::size_t i = 0; i < cells; ++i) m[i] = std::max(m[i], std::uint8_t(e[i] + 1));
  }
  for (std::size_t i = 0; i < cells; ++i) m[i] = std::uint8_t(m[i] - 1);
  inflation_.apply(master_, master_);
  return all_used;
}

std::uint8_t LayeredCostmap::cost_at_world(double x, double y) const {
  int cx = 0, cy = 0;
  if (!master_.world_to_cell(x, y, cx, cy)) return cost::kUnknown;
  return master_.at(cx, cy);
}

std::uint8_t LayeredCostmap::footprint_cost(const Pose2& pose, double half_length_m,
                                            double half_width_m) const {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw) ||
      !std::isfinite(half_length_m) || !std::isfinite(half_width_m)) {
    return cost::kUnknown;
  }
  const double hl = std::max(0.0, half_length_m), hw = std::max(0.0, half_width_m);
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  // Axis-aligned bounds of the rotated rectangle, then a centre-in-rectangle test per cell.
  const double ex = std::abs(c) * hl + std::abs(s) * hw;
  const double ey = std::abs(s) * hl + std::abs(c) * hw;
  const int x0 = master_.cell_of(pose.x - ex), x1 = master_.cell_of(pose.x + ex);
  const int y0 = master_.cell_of(pose.y - ey), y1 = master_.cell_of(pose.y + ey);
  std::uint8_t worst = cost_at_world(pose.x, pose.y);
  for (int cy = y0; cy <= y1 && worst != cost::kLethal; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      const double dx = master_.center_of(cx) - pose.x, dy = master_.center_of(cy) - pose.y;
      const double along = c * dx + s * dy, across = -s * dx + c * dy;
      if (std::abs(along) > hl || std::abs(across) > hw) continue;
      const std::uint8_t v = master_.contains(cx, cy) ? master_.at(cx, cy) : cost::kUnknown;
      if (v == cost::kLethal) return v;
      worst = std::max(worst, v);
    }
  }
  return worst;
}

}  // namespace carril::fw
