#include "host_sim/sensors/LidarSim.hpp"

#include <cmath>
#include <limits>

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

namespace {
constexpr double kDeg = fw::kPi / 180.0;

}  // namespace

LidarSim::LidarSim(const LidarSpec& spec, std::uint64_t seed)
    : spec_(spec),
      rng_(seed ^ 0x1D4A5ULL),
      noise_(0.0, spec.noise_std_m > 0 ? spec.noise_std_m : 1.0),
      drop_rng_(seed ^ 0xD409B0ULL) {
  const double fov = spec_.fov_deg * kDeg;
  const int n = spec_.beams;
  // A full circle has no end beam: spread the beams so the last does not repeat the first.
  inc_rad_ = fov >= 2 * fw::kPi - 1e-9 ? fov / n : fov / (n - 1);
  beam_cos_.resize(std::size_t(n > 0 ? n : 0));
  beam_sin_.resize(beam_cos_.size());
  for (int i = 0; i < n; ++i) {
    const double a = spec_.yaw_deg * kDeg - fov / 2 + i * inc_rad_;
    beam_cos_[std::size_t(i)] = std::cos(a);
    beam_sin_[std::size_t(i)] = std::sin(a);
  }
}

void LidarSim::scan(const SimWorld& world, hal::LaserScan& out) {
  const Pose2 p = world.pose();
  const double co = std::cos(p.yaw_rad), si = std::sin(p.yaw_rad);
  const double ox = p.x + co * spec_.x_m - si * spec_.y_m;
  const double oy = p.y + si * spec_.x_m + co * spec_.y_m;
  const double fov = spec_.fov_deg * kDeg;
  const int n = spec_.beams;
  const double inc = inc_rad_;
  out.count = static_cast<std::uint16_t>(n);
  out.angle_min_rad = float(-fov / 2);
  out.angle_increment_rad = float(inc);
  out.range_min_m = float(spec_.range_min_m);
  out.range_max_m = float(spec_.range_max_m);
  const b2Vec2 origin{float(ox), float(oy)};
  caster_.prepare(world.world(), world.robot_body());  // every body but the robot's own
  for (int i = 0; i < n; ++i) {
    const double bc = beam_cos_[std::size_t(i)], bs = beam_sin_[std::size_t(i)];
    const double c = co * bc - si * bs, s = si * bc + co * bs;  // of the beam's world angle
    const b2Vec2 end{float(ox + c * spec_.range_max_m), float(oy + s * spec_.range_max_m)};
    const float best = caster_.cast(origin, end);
    float r = std::numeric_limits<float>::infinity();
    if (best <= 1.0F) {
      double d = double(best) * spec_.range_max_m;
      if (spec_.noise_std_m > 0) d += noise_(rng_);
      r = float(std::max(d, spec_.range_min_m));
    }
    if (spec_.dropout > 0.0 && drop_(drop_rng_) < spec_.dropout) {
      r = std::numeric_limits<float>::infinity();
    }
    out.ranges_m[std::size_t(i)] = r;
  }
}

}  // namespace carril::sim
