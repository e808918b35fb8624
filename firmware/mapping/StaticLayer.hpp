#pragma once
// The static map as a costmap layer: the window's cells read from the OccupancyGrid (a wall is
// lethal, free space free, the unsurveyed unknown). The map is in the costmap's frame (the map
// frame, where the localised robot drives). Filled at init and after the window moves; the map
// and the window may have different origins (each window cell takes the map cell under its
// centre) but must share the resolution.
#include <cstdint>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

class StaticLayer {
 public:
  // Allocates the window (init time); an error naming the window when that fails.
  Status init(int nx, int ny, double resolution_m);
  // Moves the window so that (x, y) [m] is its centre cell and reads every cell from the map
  // (init time, or whenever the window moves: it costs the whole window).
  void place(const OccupancyGrid& map, double x, double y);
  const RollingGrid<std::uint8_t>& grid() const { return grid_; }

 private:
  RollingGrid<std::uint8_t> grid_;
};

}  // namespace carril::fw
