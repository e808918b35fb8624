#pragma once
// A static occupancy map in the map frame (the frame a map file and the simulator's world share):
// the building as it was surveyed. Cells hold Nav2 cost values (CostValues.hpp): kFree (0),
// kLethal (254, occupied) or kUnknown (255, unknown), row-major from the lower-left cell:
// cell (i, j) is centred at origin + ((i + 0.5) res, (j + 0.5) res). Storage is sized at init to
// the configured capacity; assign() copies a map in and refuses one bigger than that.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct MapInfo {
  int nx = 0, ny = 0;          // cells along x and y
  double resolution_m = 0.05;  // cell side [m]
  double origin_x_m = 0.0;     // world x of the lower-left corner of cell (0, 0) [m]
  double origin_y_m = 0.0;     // world y of that corner [m]

  Status validate() const;
};

class OccupancyGrid {
 public:
  // An empty grid with no storage (no map configured).
  OccupancyGrid() = default;
  // Storage for up to max_cells cells (init time).
  explicit OccupancyGrid(std::size_t max_cells);

  // Copies a map in (init time): cells is nx * ny bytes, each kFree, kLethal or kUnknown.
  // An error names what is wrong (an invalid info, more cells than the capacity, another value).
  Status assign(const MapInfo& info, const std::uint8_t* cells);

  bool empty() const { return info_.nx == 0 || info_.ny == 0; }
  const MapInfo& info() const { return info_; }
  std::size_t capacity() const { return capacity_; }
  int nx() const { return info_.nx; }
  int ny() const { return info_.ny; }
  double resolution() const { return info_.resolution_m; }

  bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < info_.nx && j < info_.ny; }
  // Cell (i, j); kUnknown outside the map.
  std::uint8_t at(int i, int j) const {
    return contains(i, j)
               ? cells_[static_cast<std::size_t>(j) * static_cast<std::size_t>(info_.nx) +
                        static_cast<std::size_t>(i)]
               : std::uint8_t{255};
  }
  // The cell a world point [m] falls in; false outside the map (i, j still set).
  bool cell_of(double x, double y, int& i, int& j) const;
  // Centre of cell (i, j) in the world [m].
  Vec2 centre(int i, int j) const {
    return {info_.origin_x_m + (i + 0.5) * info_.resolution_m,
            info_.origin_y_m + (j + 0.5) * info_.resolution_m};
  }
  bool is_free(int i, int j) const { return at(i, j) == 0; }
  // Row-major cells from the lower-left one.
  const std::uint8_t* data() const { return cells_.get(); }

 private:
  MapInfo info_;
  std::size_t capacity_ = 0;
  std::unique_ptr<std::uint8_t[]> cells_;
};

}  // namespace carril::fw
