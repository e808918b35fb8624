#pragma once
// Simulated 3D lidar (a Velodyne HDL-32E by default: 32 rings over 41.3 deg, 1800 azimuths, 10 Hz)
// by ray marching against the world's surface (HeightQuery: terrain and obstacle tops). The first
// point where a beam goes below the surface is its return, so occlusion comes for free: the ground
// just beyond a step down or behind a box is not seen. Returns nearer than range_min_m (the blind
// zone) or farther than range_max_m give no point.
#include <cstdint>
#include <random>
#include <vector>

#include "firmware/core/Status.hpp"
#include "hal/PointCloud.hpp"
#include "host_sim/sensors/Normal.hpp"
#include "host_sim/world/HeightQuery.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::sim {

// The sensor as the robot preset describes it (`lidar3d:`), plus how finely the simulator marches
// its beams. March step at range t: clamp(t * march_step_per_m, march_step_min_m,
// march_step_max_m); a crossing is then refined by bisection to 0.5 mm. A feature thinner than the
// step at its range (e.g. 10 cm at 10 m with the defaults) can be missed.
struct Lidar3dConfig {
  loader::Lidar3dSpec sensor;
  double march_step_min_m = 0.02;  // step near the sensor [m]
  double march_step_per_m = 0.01;  // step growth with range [m per m of range]
  double march_step_max_m = 0.10;  // step far away [m]
  // Every field in its bounds (the same as the loader's); the message names the key.
  fw::Status validate() const;
};

// The robot body's pose in the world: (x, y) of its reference point, z the floor height there,
// roll/pitch/yaw as in REP 103 (R = Rz(yaw) Ry(pitch) Rx(roll)): pitch > 0 is nose DOWN, so a robot
// driving up a ramp has pitch < 0; roll > 0 is left side up.
struct BodyPose3 {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;                 // [m]
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;  // [rad]
};

class Lidar3dSim {
 public:
  // Precomputes the beam directions (allocates here, never in render). cfg must validate().
  Lidar3dSim(const Lidar3dConfig& cfg, std::uint64_t seed);

  // One sweep from the body pose into out: points in the SENSOR frame (x forward, y left, z up),
  // azimuth-major (all rings of one azimuth, then the next), beams without a return left out;
  // out.seq increments, out.stamp_ns = stamp_ns [ns]. Deterministic for a seed and call sequence.
  void render(const HeightQuery& world, const BodyPose3& body, hal::TimeNs stamp_ns,
              hal::PointCloud& out);

  // Sweep period [ns] (1 / rate_hz): the simulator calls render() at this interval.
  hal::TimeNs period_ns() const { return period_ns_; }
  // Height-surface queries made by the last render() (cost figure for benchmarks).
  std::uint64_t last_queries() const { return queries_; }
  const Lidar3dConfig& config() const { return cfg_; }

  // Elevation of ring r [rad] and azimuth of firing a [rad] in the sensor frame.
  double ring_elevation_rad(int r) const;
  double azimuth_rad(int a) const;

 private:
  // Range [m] of the first crossing below the surface along unit direction d from o, or < 0.
  double cast(const HeightQuery& world, double ox, double oy, double oz, double dx, double dy,
              double dz, double max_h, double min_h);

  Lidar3dConfig cfg_;
  hal::TimeNs period_ns_;
  std::uint32_t seq_ = 0;
  std::uint64_t queries_ = 0;
  std::mt19937_64 rng_;
  Normal noise_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  // Unit beam directions in the sensor frame: ring elevation (sin, cos), azimuth (cos, sin).
  std::vector<double> sin_el_, cos_el_, cos_az_, sin_az_;
};

}  // namespace carril::sim
