#pragma once
// A tiny 2D scene of segments and discs that tests cast a lidar's beams into, so a scan is what a
// real sensor at that pose would return (walls, a pillar, a person) rather than hand-placed
// ranges.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "firmware/core/Geometry.hpp"
#include "hal/Types.hpp"

namespace carril::fw::test {

struct ScanScene {
  struct Segment {
    Vec2 a, b;
  };
  struct Disc {
    Vec2 c;
    double r;
  };
  std::vector<Segment> segments;
  std::vector<Disc> discs;

  // The nearest hit along a ray from o in unit direction d, or +inf.
  double cast(const Vec2& o, const Vec2& d) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments) {
      const Vec2 e = s.b - s.a;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::fabs(den) < 1e-12) continue;
      const Vec2 w = s.a - o;
      const double t = (w.x() * e.y() - w.y() * e.x()) / den;
      const double u = (w.x() * d.y() - w.y() * d.x()) / den;
      if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::fmin(best, t);
    }
    for (const Disc& c : discs) {
      const Vec2 w = o - c.c;
      const double b = w.dot(d), q = w.squaredNorm() - c.r * c.r;
      const double disc = b * b - q;
      if (disc < 0.0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 0.0) best = std::fmin(best, t);
    }
    return best;
  }

  // A scan of `beams` beams over `fov_rad` centred on the sensor's x, from a sensor at `mount`
  // (robot frame) on a robot at `pose`; beyond range_max there is no return (+inf).
  std::unique_ptr<hal::LaserScan> scan(const Pose2& pose, const Pose2& mount, int beams,
                                       double fov_rad, double range_max = 20.0) const {
    auto s = std::make_unique<hal::LaserScan>();
    s->seq = 1;
    s->count = static_cast<std::uint16_t>(beams);
    s->angle_min_rad = float(-0.5 * fov_rad);
    s->angle_increment_rad = float(fov_rad / (beams - 1));
    s->range_min_m = 0.05F;
    s->range_max_m = float(range_max);
    const Vec2 o = to_world(pose, Vec2(mount.x, mount.y));
    for (int i = 0; i < beams; ++i) {
      const double a =
          pose.yaw + mount.yaw + double(s->angle_min_rad) + i * double(s->angle_increment_rad);
      const double r = cast(o, Vec2(std::cos(a), std::sin(a)));
      s->ranges_m[std::size_t(i)] =
          r <= range_max ? float(r) : std::numeric_limits<float>::infinity();
    }
    return s;
  }
};

}  // namespace carril::fw::test
