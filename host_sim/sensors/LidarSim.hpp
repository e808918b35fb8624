#pragma once
// 2D lidar by Box2D ray casts from the mount pose (RayCaster: the closest hits b2World::RayCast
// finds); ranges get Gaussian noise. A beam with no hit within range_max reports +inf (the
// convention real drivers use for "nothing seen"), as does a dropped beam (LidarSpec::dropout: each
// beam of each scan lost with that probability).
#include <cstdint>
#include <random>
#include <vector>

#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/sensors/Normal.hpp"
#include "host_sim/sensors/RayCaster.hpp"
#include "host_sim/world/SimWorld.hpp"

namespace carril::sim {

class LidarSim {
 public:
  LidarSim(const LidarSpec& spec, std::uint64_t seed);
  void scan(const SimWorld& world, hal::LaserScan& out);

 private:
  LidarSpec spec_;
  std::mt19937_64 rng_;
  Normal noise_;
  std::mt19937_64 drop_rng_;  // its own: dropping beams does not move the noise's draws
  std::uniform_real_distribution<double> drop_{0.0, 1.0};
  RayCaster caster_;  // the world's fixtures, gathered once per scan
  // cos and sin of each beam's angle on the robot (mount yaw included), fixed by the spec: a
  // beam's world direction is this turned by the robot's yaw, not a sincos per beam per scan.
  std::vector<double> beam_cos_, beam_sin_;
  double inc_rad_ = 0.0;  // between neighbouring beams [rad]
};

}  // namespace carril::sim
