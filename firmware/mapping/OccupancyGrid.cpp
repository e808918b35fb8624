#include "firmware/mapping/OccupancyGrid.hpp"

#include <cmath>
#include <cstring>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

Status MapInfo::validate() const {
  if (nx <= 0 || ny <= 0)
    return Status::error("map: size %d x %d cells, expected at least 1 x 1", nx, ny);
  if (!(std::isfinite(resolution_m) && resolution_m > 0.0)) {
    return Status::error("map.resolution: %g m, expected a finite number > 0", resolution_m);
  }
  if (!std::isfinite(origin_x_m) || !std::isfinite(origin_y_m)) {
    return Status::error("map.origin: (%g, %g) m, expected finite", origin_x_m, origin_y_m);
  }
  return Status::ok();
}

OccupancyGrid::OccupancyGrid(std::size_t max_cells)
    : capacity_(max_cells), cells_(new std::uint8_t[max_cells]) {}

Status OccupancyGrid::assign(const MapInfo& info, const std::uint8_t* cells) {
  if (Status s = info.validate(); !s) return s;
  const std::size_t n = static_cast<std::size_t>(info.nx) * static_cast<std::size_t>(info.ny);
  if (n > capacity_) {
    return Status::error("map: %d x %d = %zu cells, the static map buffer holds %zu (raise %s)",
                         info.nx, info.ny, n, capacity_, "localisation.max_map_cells");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t v = cells[k];
    if (v != cost::kFree && v != cost::kLethal && v != cost::kUnknown) {
      return Status::error(
          "map: cell (%zu, %zu) holds %u, expected 0 (free), 254 (occupied) or "
          "255 (unknown)",
          k % static_cast<std::size_t>(info.nx), k / static_cast<std::size_t>(info.nx),
          static_cast<unsigned>(v));
    }
  }
  std::memcpy(cells_.get(), cells, n);
  info_ = info;
  return Status::ok();
}

bool OccupancyGrid::cell_of(double x, double y, int& i, int& j) const {
  const double fx = (x - info_.origin_x_m) / info_.resolution_m;
  const double fy = (y - info_.origin_y_m) / info_.resolution_m;
  // Clamp before converting: a point far off the map must not overflow int.
  i = static_cast<int>(std::floor(clampd(fx, -1.0, static_cast<double>(info_.nx))));
  j = static_cast<int>(std::floor(clampd(fy, -1.0, static_cast<double>(info_.ny))));
  return contains(i, j);
}

}  // namespace carril::fw
