#pragma once
// Traversability costs for one robot profile from a TerrainAnalysis, with Nav2's cost values:
// lethal where the slope or a step exceeds the profile's limit, unknown where the terrain is not
// known, graded in between (rising with slope / max_slope and step / max_step) so that planners
// prefer flatter ground. The elevation map is shared; each profile derives its own layer.
#include <cstdint>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/TerrainAnalysis.hpp"

namespace carril::fw {

struct TraversabilityProfile {
  double max_slope_deg = 8.0;     // steepest slope the robot may drive [deg]
  double max_step_up_m = 0.03;    // highest step up it may climb [m]
  double max_step_down_m = 0.10;  // deepest step down it may take [m]
  int graded_cost_max = 200;      // cost at the limits (0 on flat ground) [1..252]

  Status validate() const;
  bool operator==(const TraversabilityProfile&) const = default;
};

class TraversabilityLayer {
 public:
  // Allocates the nx x ny grid at resolution_m [m], all unknown (init time only).
  Status init(int nx, int ny, double resolution_m);
  // Unobserved cells within radius_m [m] of (x, y) [m] are free: the blind zone round the start
  // pose, which the lidar never sees. Remembered (a mask in the odometry frame); once a cell is
  // observed, its terrain decides. Call once, at start.
  void mark_start_free(double x, double y, double radius_m);
  // Recomputes the cells of the analysis' last computed rectangle (the window follows the
  // analysis' window). No allocation.
  void update(const TerrainAnalysis& terrain, const TraversabilityProfile& profile);
  // Moves the window to global cell origin (cx, cy) ahead of the analysis (cells that enter are
  // unknown until it reaches them), so that the layer can be combined while a cycle runs.
  void move_window(int origin_cx, int origin_cy) { grid_.move_origin(origin_cx, origin_cy); }

  // Cost of one cell from its terrain figures [rad, m, m, m].
  static std::uint8_t classify(TerrainStatus status, float slope_rad, float step_up_m,
                               float step_down_m, float drop_m, const TraversabilityProfile& p);

  const RollingGrid<std::uint8_t>& grid() const { return grid_; }

 private:
  bool in_start_area(int cx, int cy) const;

  RollingGrid<std::uint8_t> grid_;
  bool start_set_ = false;
  double start_x_ = 0.0, start_y_ = 0.0, start_r2_ = 0.0;
};

}  // namespace carril::fw
