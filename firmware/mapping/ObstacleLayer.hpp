#pragma once
// Obstacle layer of the costmap: a robot-centred grid of kUnknown / kFree / kLethal built from 2D
// lidar scans. A hit inside the marking range marks its cell lethal; the ray from the sensor to
// the hit (or to the clearing range when nothing was returned) clears the cells it crosses.
//
// Persistence (Nav2 loses obstacles that leave the field of view and keeps ghosts of removed
// ones, navigation2 #545, #5476). Here a cell changes only on evidence:
//  - cells no ray of the scan crosses keep their state, so an obstacle behind the robot or
//    outside a 180 deg field of view stays where it was seen;
//  - a hit marks at once (a real obstacle must never wait);
//  - a lethal cell is cleared only after rays have crossed it in `clear_scans` different scans
//    with no hit in between (a hit re-arms the count). One noisy beam or one scan where a thin
//    obstacle was missed cannot erase it; a removed obstacle is gone after clear_scans scans.
//    Counting scans, not rays, matters: near the sensor a cell is crossed by several beams of
//    one scan, which would otherwise clear it at once.
//  - optionally, a lethal cell not hit for decay_s returns to unknown (for sensors that cannot
//    see the cell any more, e.g. a moved obstacle now hidden behind another). 0 = off.
// A per-cell counter was chosen over int8 log-odds: it has the same hysteresis with a number a
// user can tune ("cleared after 3 scans") and exact, testable behaviour.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "firmware/core/BeamDirections.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct ObstacleLayerConfig {
  double obstacle_max_range_m = 5.0;  // hits farther than this are not marked [m]
  double raytrace_max_range_m = 6.0;  // rays clear up to this distance [m]
  double raytrace_min_range_m = 0.0;  // rays clear from this distance on [m]
  int clear_scans = 3;                // scans crossing a lethal cell needed to clear it [scans]
  double decay_s = 0.0;  // lethal cells not hit for this long become unknown; 0 off [s]

  Status validate() const;
  bool operator==(const ObstacleLayerConfig&) const = default;
};

// What one update() did with the beams (for health counters and tests).
struct ObstacleUpdateStats {
  int marked = 0;   // beams that marked a cell
  int cleared = 0;  // beams that cleared (hits beyond the marking range and +inf included)
  int ignored = 0;  // NaN, 0, -inf, below range_min, or the scan/pose is unusable
};

class ObstacleLayer {
 public:
  // Allocates the grids (init time) for a window of nx x ny cells of resolution_m [m].
  // cfg must have passed validate().
  bool init(const ObstacleLayerConfig& cfg, int nx, int ny, double resolution_m);

  // Integrates one scan taken with the lidar at sensor_pose (odometry/world frame: x, y [m],
  // yaw [rad]); scan.stamp_ns drives the decay. Never allocates.
  ObstacleUpdateStats update(const hal::LaserScan& scan, const Pose2& sensor_pose);

  // Moves the window so that (x, y) [m] is its centre cell; cells that stay keep their state.
  void recenter(double x, double y);
  // Forgets everything (all unknown).
  void clear();

  // Test reference: rays from the sensor walk every cell, not skipping the free square round it.
  void walk_every_cell(bool on) { walk_every_cell_ = on; }
  // Steps the last scan's rays from the sensor did not walk (the free square round it) [cells].
  int skipped_steps() const { return free_skip_; }

  // kUnknown / kFree / kLethal per cell.
  const RollingGrid<std::uint8_t>& grid() const { return cost_; }
  const ObstacleLayerConfig& config() const { return cfg_; }

 private:
  // Per-cell memory for the hysteresis and the decay.
  struct CellState {
    std::uint8_t misses_left = 0;   // scans still needed to clear a lethal cell
    std::uint8_t last_miss = 0;     // low byte of the scan counter of the last counted miss
    std::uint16_t hit_time_ds = 0;  // time of the last hit, 0.1 s ticks, wrapping
  };
  void clear_ray(double x0, double y0, double x1, double y1, bool keep_end, int col_off,
                 int row_off);
  void decay(std::uint16_t now_ds);
  // The largest R (at most r_cap) such that every cell within Chebyshev distance R of the
  // global cell (cx, cy) lies in the window and is free; -1 when (cx, cy) itself is not [cells].
  int free_radius(int cx, int cy, int r_cap) const;

  ObstacleLayerConfig cfg_;
  RollingGrid<std::uint8_t> cost_;
  RollingGrid<CellState> state_;
  BeamDirections beams_;  // the beams' directions in the sensor frame, kept across scans
  // This scan's hit cells, marked last: their index in the grids' storage (cost_ and state_
  // share one layout).
  std::array<std::size_t, hal::kMaxScanBeams> hits_{};
  // The last ray's start point [m], window corner [cells] and start cell [cells].
  struct RayStart {
    double x = HUGE_VAL, y = HUGE_VAL;
    int lo_x = 0, lo_y = 0, cx = 0, cy = 0;
  };
  RayStart start_;
  // The last ray walked in this scan, by its cells [cells]: a beam that ends in the same cell as
  // the one before it (a quarter of a 541-beam scan within a few metres) walks the very same
  // cells, and a second walk changes nothing (see clear_ray), so it is skipped.
  struct LastRay {
    int cx0 = 0, cy0 = 0, cx1 = 0, cy1 = 0;
    bool include_end = false, valid = false;
    bool operator==(const LastRay&) const = default;
  };
  LastRay last_ray_;
  // This scan's sensor cell [cells] and the steps a ray from it walks through cells that were
  // free as the scan began (free_radius + 1). Clearing only frees cells and marking comes after
  // it, so those steps would change nothing: rays from that cell skip them.
  int free_cx_ = 0, free_cy_ = 0, free_skip_ = 0;
  bool walk_every_cell_ = false;
  std::uint8_t scan_counter_ = 0;
  std::uint16_t last_decay_ds_ = 0;
  bool decayed_once_ = false;
};

}  // namespace carril::fw
