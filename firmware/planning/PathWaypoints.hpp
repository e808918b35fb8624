#pragma once
// Planner cells to world waypoints: cell centres given the grid's origin and resolution, with
// the interior points of straight runs (same step direction) dropped, so a follower gets one
// waypoint per turn. No allocation.
#include <cstddef>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/planning/WavefrontPlanner.hpp"

namespace carril::fw {

// World centre of window cell c for a grid whose lower-left corner is (origin_x, origin_y) [m]
// with cells of resolution_m [m].
inline Vec2 cell_center(const GridCell& c, double origin_x, double origin_y, double resolution_m) {
  return {origin_x + (c.x + 0.5) * resolution_m, origin_y + (c.y + 0.5) * resolution_m};
}

// Writes the first cell, every cell where the step direction changes, and the last cell, as
// world points [m]. false when `out` is too small (out then holds a prefix).
template <std::size_t N>
bool cells_to_waypoints(const GridCell* cells, std::size_t n, double origin_x, double origin_y,
                        double resolution_m, StaticVector<Vec2, N>& out) {
  out.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && i + 1 < n) {
      const int dx0 = cells[i].x - cells[i - 1].x, dy0 = cells[i].y - cells[i - 1].y;
      const int dx1 = cells[i + 1].x - cells[i].x, dy1 = cells[i + 1].y - cells[i].y;
      if (dx0 == dx1 && dy0 == dy1) continue;  // inside a straight run
    }
    if (!out.try_push_back(cell_center(cells[i], origin_x, origin_y, resolution_m))) return false;
  }
  return true;
}

}  // namespace carril::fw
