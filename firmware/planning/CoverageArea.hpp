#pragma once
// What a coverage mission has to sweep, from the static map: the cells where the robot's centre
// may stand (free cells farther than its radius from every occupied or unknown cell and from the
// map's edge, inside the area's polygon when there is one) and the cells its tool can sweep from
// there (free cells, inside the polygon, within the tool's reach of such a centre cell), each with
// its anchor: the nearest centre cell, where the robot stands to sweep it.
//
// The reach is tool_width / 2 less a margin (half a cell by default): a lane held to a few
// millimetres must still pass over the cell's centre. The simulator scores a run against the
// same coverable cells (the reachable free area), the mission counts its own coverage on them.
//
// Buffers are sized by the constructor; build() is init-time work (O(boundary cells * r^2)),
// keep_component() and keep_anchored() are O(cells) and never allocate.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

struct CoverageAreaConfig {
  double robot_radius_m = 0.25;  // the centre keeps farther than this from obstacles [m]
  double tool_width_m = 0.5;     // the tool's width across the heading [m]
  double reach_margin_m = -1.0;  // reach = tool_width / 2 - this; < 0: half a cell [m]
  // Centre cells keep robot_radius from the nearest point of each occupied cell's square, not
  // from its centre: a door jamb's corner is then as far as a wall's face (the mission's own
  // area; the simulator scores against centre distances).
  bool box_distance = false;
  const Vec2* polygon = nullptr;  // the area's corners, map frame [m]; nullptr: the whole map
  std::size_t polygon_size = 0;   // corners (3 or more when a polygon is given)
};

// Even-odd rule: p inside the polygon pts[0..n) (n >= 3).
bool point_in_polygon(const Vec2& p, const Vec2* pts, std::size_t n);

class CoverageArea {
 public:
  static constexpr std::int32_t kNoAnchor = -1;

  // Buffers for maps up to max_cells cells (init time).
  explicit CoverageArea(std::size_t max_cells);

  // Builds both masks from the map (init time). An error names what is wrong: no map, a map
  // larger than the buffers, a bad setting, or an area with no cell where the robot fits.
  Status build(const OccupancyGrid& map, const CoverageAreaConfig& cfg);

  // Keeps the centre cells 4-connected to centre cell (i, j) and the coverable cells anchored on
  // them; false (nothing changed) when (i, j) is no centre cell.
  bool keep_component(int i, int j);
  // Keeps the coverable cells whose anchor (a row-major index) satisfies reachable(index).
  template <typename Reachable>
  void keep_anchored(Reachable reachable) {
    coverable_cells_ = 0;
    for (std::size_t k = 0; k < n_; ++k) {
      if (coverable_[k] == 0) continue;
      if (anchor_[k] < 0 || !reachable(static_cast<std::size_t>(anchor_[k]))) {
        coverable_[k] = 0;
      } else {
        ++coverable_cells_;
      }
    }
  }

  const MapInfo& info() const { return info_; }
  std::size_t size() const { return n_; }
  double reach_m() const { return reach_m_; }
  // Row-major masks from the lower-left cell: non-zero where the robot's centre may stand / where
  // the tool can sweep.
  const std::uint8_t* centre() const { return centre_.get(); }
  const std::uint8_t* coverable() const { return coverable_.get(); }
  // The nearest centre cell of coverable cell k (row-major index), kNoAnchor for other cells.
  std::int32_t anchor(std::size_t k) const { return anchor_[k]; }
  std::size_t centre_cells() const { return centre_cells_; }
  std::size_t coverable_cells() const { return coverable_cells_; }

 private:
  std::size_t capacity_;
  MapInfo info_;
  std::size_t n_ = 0;
  double reach_m_ = 0.0;
  std::unique_ptr<std::uint8_t[]> centre_, coverable_;
  std::unique_ptr<std::int32_t[]> anchor_;
  std::unique_ptr<std::uint16_t[]> best_;  // squared distance to the anchor [cells^2]
  std::unique_ptr<std::int32_t[]> queue_;
  std::size_t centre_cells_ = 0, coverable_cells_ = 0;
};

}  // namespace carril::fw
