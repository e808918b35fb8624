#pragma once
// Elevation map: a robot-centred RollingGrid<ElevationCell> fed with 3D lidar sweeps. Each cell
// keeps a height and its variance with a 1D Kalman update per sweep, as ANYbotics'
// elevation_mapping does: the measurement variance grows with range, a measurement far ABOVE the
// estimate replaces it (something new stands there), one far BELOW inflates the variance (a
// removed obstacle is re-learned after a few sweeps), and variances grow with time (process noise)
// so stale cells are re-learned.
//
// Per sweep and cell the HIGHEST point is the cell's measurement (elevation_mapping keeps the max
// too): an obstacle's top counts, and the ground seen through the edge of a cell does not
// average a step away.
#include <cstdint>
#include <memory>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/ElevationCell.hpp"
#include "firmware/mapping/Pose3Tracker.hpp"
#include "hal/PointCloud.hpp"

namespace carril::fw {

struct ElevationConfig {
  double size_x_m = 12.0;                // window width [m]
  double size_y_m = 12.0;                // window height [m]
  double resolution_m = 0.05;            // cell side [m]
  double min_range_m = 0.5;              // closer points are the robot's own body [m]
  double max_range_m = 20.0;             // farther points are ignored [m]
  double noise_sigma_m = 0.01;           // range noise model: sigma = noise_sigma_m + ... [m]
  double noise_range_coeff = 0.0005;     // ... + noise_range_coeff * range^2 [1/m]
  double gate_sigmas = 3.0;              // Mahalanobis gate [sigma]
  double gate_offset_m = 0.03;           // plus this margin before a higher point replaces [m]
  double multi_height_noise_m2 = 0.01;   // added to a cell's variance per sweep that sees it far
                                         // below its estimate [m^2]
  double process_noise_m2_per_s = 1e-5;  // variance growth with time [m^2/s]
  double max_variance_m2 = 0.25;         // cap of the growth [m^2]
  // true: points are rotated by the full sensor attitude (a gravity-aligned map, the IMU's
  // pitch and roll compensated exactly). false: by yaw only, as a system without IMU
  // compensation does (the sensor pose's roll and pitch are ignored).
  bool use_imu_attitude = true;

  Status validate() const;
  bool operator==(const ElevationConfig&) const = default;
};

class ElevationLayer {
 public:
  // Allocates the grid and the per-sweep scratch (init time only).
  Status init(const ElevationConfig& config);
  // Moves the window so that (x, y) [m] is in its centre; cells that leave are forgotten.
  void recenter(double x, double y) { grid_.recenter(x, y); }
  // Fuses one sweep seen from `sensor_pose` (odometry frame). Non-finite points and points out
  // of [min_range_m, max_range_m] are skipped. The time since the previous sweep's stamp first
  // grows every observed cell's variance. No allocation.
  void fuse(const hal::PointCloud& cloud, const Pose3& sensor_pose);
  // The same in pieces, to spread a sweep over ticks: begin_sweep(), then bin_points() over
  // consecutive ranges of the cloud (each point once), then fuse_step() until it returns true
  // (or end_sweep()), which alone change the map. A begin_sweep() before the first fuse_step()
  // abandons the sweep in progress, the map unchanged. The window must not move in between.
  // begin_sweep() returns false (nothing started) for a non-finite pose.
  bool begin_sweep(std::int64_t stamp_ns, const Pose3& sensor_pose);
  // Bins points [first, first + count) of `cloud` (clipped to its count) into the sweep.
  void bin_points(const hal::PointCloud& cloud, std::uint32_t first, std::uint32_t count);
  // Fuses up to max_cells of the binned cells (the first call only ages every cell's variance,
  // one sequential pass over the window); true when the sweep is complete.
  bool fuse_step(std::uint32_t max_cells);
  void end_sweep();
  // Grows every observed cell's variance by process_noise * dt_s [s] (fuse() does it itself).
  void add_process_noise(double dt_s);

  const RollingGrid<ElevationCell>& grid() const { return grid_; }
  RollingGrid<ElevationCell>& grid() { return grid_; }
  const ElevationConfig& config() const { return config_; }
  // Points used by the last fuse() and cells they updated.
  std::uint32_t last_points_used() const { return last_points_; }
  std::uint32_t last_cells_updated() const { return last_cells_; }

 private:
  ElevationConfig config_;
  RollingGrid<ElevationCell> grid_;
  // Per-sweep scratch, window-local index ly * nx + lx: the sweep's highest point per cell.
  std::unique_ptr<std::uint32_t[]> mark_;  // sweep number that last wrote the cell
  std::unique_ptr<float[]> scan_z_;
  std::unique_ptr<float[]> scan_var_;
  std::unique_ptr<std::uint32_t[]> touched_;  // local indices written this sweep
  std::uint32_t sweep_ = 0;
  // The sweep in progress: sensor rotation, its position in cells from the window's corner.
  bool in_sweep_ = false, fusing_ = false;
  float r_[9] = {};
  float tx_ = 0.0F, ty_ = 0.0F, tz_ = 0.0F;
  std::uint32_t used_ = 0, touched_count_ = 0, next_touched_ = 0;
  std::int64_t sweep_stamp_ns_ = 0;
  void grow_variances_to(std::int64_t stamp_ns);
  std::int64_t last_stamp_ns_ = -1;
  std::uint32_t last_points_ = 0, last_cells_ = 0;
};

}  // namespace carril::fw
