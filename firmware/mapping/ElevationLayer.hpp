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

#include "firmware/core/Status.hpp"
#include "firmware/mapping/ElevationCell.hpp"
#include "firmware/mapping/Pose3Tracker.hpp"
#include "firmware/mapping/RollingGrid.hpp"
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
  std::int64_t last_stamp_ns_ = -1;
  std::uint32_t last_points_ = 0, last_cells_ = 0;
};

}  // namespace carril::fw
