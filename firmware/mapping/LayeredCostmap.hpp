#pragma once
// The robot-centred costmap: an obstacle layer it owns, any extra layers of the same window
// (traversability, ...), combined into a master grid and inflated. Everything is allocated by
// init(); recenter(), update_obstacles() and update_master() never allocate.
//
// Combination per cell: lethal if any layer is lethal, unknown only if every layer is unknown,
// otherwise the largest known cost. Then the lethal cells are inflated (InflationLayer).
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/InflationLayer.hpp"
#include "firmware/mapping/ObstacleLayer.hpp"

namespace carril::fw {

struct CostmapConfig {
  double size_x_m = 12.0;      // window width [m]
  double size_y_m = 12.0;      // window height [m]
  double resolution_m = 0.05;  // cell side [m]
  ObstacleLayerConfig obstacle;
  InflationConfig inflation;

  Status validate() const;
  int nx() const;  // window width [cells]
  int ny() const;  // window height [cells]
  bool operator==(const CostmapConfig&) const = default;
};

class LayeredCostmap {
 public:
  // Validates cfg and allocates the master grid and the owned layers (init time).
  Status init(const CostmapConfig& cfg);

  // Moves every owned grid so that (x, y) [m] is the window's centre cell. Extra layers passed to
  // update_master() must be moved to the same window by their owner.
  void recenter(double x, double y);

  // Integrates a 2D scan into the obstacle layer (see ObstacleLayer::update).
  ObstacleUpdateStats update_obstacles(const hal::LaserScan& scan, const Pose2& sensor_pose) {
    return obstacles_.update(scan, sensor_pose);
  }

  // Rebuilds the master: obstacle layer and extra_layers[0..n) combined, then inflated. Extra
  // layers must cover the same window (size, resolution, origin); one that does not is skipped
  // and the call returns false.
  bool update_master(const RollingGrid<std::uint8_t>* const extra_layers[], int n);
  bool update_master() { return update_master(nullptr, 0); }

  // Readouts (plots, planners).
  const RollingGrid<std::uint8_t>& master() const { return master_; }
  const RollingGrid<std::uint8_t>& obstacle_layer() const { return obstacles_.grid(); }
  ObstacleLayer& obstacles() { return obstacles_; }
  const InflationLayer& inflation() const { return inflation_; }
  const CostmapConfig& config() const { return cfg_; }

  // Master cost at the world point (x, y) [m]; kUnknown outside the window or for NaN.
  std::uint8_t cost_at_world(double x, double y) const;

  // Highest master cost over the cells whose centres lie in the rectangle centred on pose,
  // half_length_m along its yaw and half_width_m across [m]: kLethal if any such cell is lethal,
  // else the max (kUnknown if any is unknown or outside the window). The cell under the pose is
  // always included, so a rectangle smaller than a cell still reads one cell.
  std::uint8_t footprint_cost(const Pose2& pose, double half_length_m, double half_width_m) const;

 private:
  CostmapConfig cfg_;
  ObstacleLayer obstacles_;
  InflationLayer inflation_;
  RollingGrid<std::uint8_t> master_;
};

}  // namespace carril::fw
