#include "host_sim/world/HeightField.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

namespace {
double tan_deg(double deg) {
  return std::tan(deg * fw::kPi / 180.0);
}
}  // namespace

HeightField::HeightField(const std::vector<TerrainSpec>& terrain,
                         const std::vector<ObstacleSpec>& obstacles) {
  features_.reserve(terrain.size());
  for (const TerrainSpec& t : terrain) {
    Feature f;
    f.type = t.type;
    f.cx = t.center.x;
    f.cy = t.center.y;
    f.c = std::cos(t.yaw_rad);
    f.s = std::sin(t.yaw_rad);
    f.hu = t.footprint_length_m() / 2.0;
    f.hv = t.width_m / 2.0;
    const double ex = std::abs(f.c) * f.hu + std::abs(f.s) * f.hv;
    const double ey = std::abs(f.s) * f.hu + std::abs(f.c) * f.hv;
    f.xmin = f.cx - ex;
    f.xmax = f.cx + ex;
    f.ymin = f.cy - ey;
    f.ymax = f.cy + ey;
    double lo = 0.0, hi = 0.0;
    if (t.type == TerrainType::Ramp) {
      // Up the first section, up the second (if any), the top, then the same down in reverse.
      auto knot = [&f](double s, double z) {
        f.knot_s[f.knots] = s;
        f.knot_z[f.knots] = z;
        ++f.knots;
      };
      double s = 0.0, z = 0.0;
      knot(s, z);
      s += t.length_m;
      z += t.length_m * tan_deg(t.angle_deg);
      knot(s, z);
      if (t.length2_m > 0.0) {
        s += t.length2_m;
        z += t.length2_m * tan_deg(t.angle2_deg);
        knot(s, z);
      }
      hi = z;
      if (t.top_m > 0.0) {
        s += t.top_m;
        knot(s, z);
      }
      if (t.descend) {
        if (t.length2_m > 0.0) {
          s += t.length2_m;
          z -= t.length2_m * tan_deg(t.angle2_deg);
          knot(s, z);
        }
        s += t.length_m;
        knot(s, 0.0);
      }
    } else {
      f.z = t.type == TerrainType::Step ? t.height_m : -t.depth_m;
      lo = std::min(0.0, f.z);
      hi = std::max(0.0, f.z);
    }
    max_z_ = std::max(max_z_, hi);
    min_z_ = std::min(min_z_, lo);
    features_.push_back(f);
  }
  // Obstacles stand on the ground under their centre.
  tops_.reserve(obstacles.size());
  for (const ObstacleSpec& o : obstacles) {
    Top p;
    p.box = o.shape == ObstacleShape::Box;
    p.cx = o.center.x;
    p.cy = o.center.y;
    p.c = std::cos(o.yaw_rad);
    p.s = std::sin(o.yaw_rad);
    p.hx = o.size_x_m / 2.0;
    p.hy = o.size_y_m / 2.0;
    p.r = o.radius_m;
    p.z_top = ground_at(o.center.x, o.center.y) + o.height_m;
    max_z_ = std::max(max_z_, p.z_top);
    tops_.push_back(p);
  }
}

// Height and slope along u of a ramp at u (in [-hu, hu]); false outside the profile.
bool HeightField::profile(const Feature& f, double u, double& z, double& dzdu) {
  const double s = u + f.hu;
  for (int i = 0; i + 1 < f.knots; ++i) {
    const double s0 = f.knot_s[i], s1 = f.knot_s[i + 1];
    if (s <= s1 || i + 2 == f.knots) {
      const double len = s1 - s0;
      dzdu = len > 0.0 ? (f.knot_z[i + 1] - f.knot_z[i]) / len : 0.0;
      z = f.knot_z[i] + dzdu * std::clamp(s - s0, 0.0, len);
      return true;
    }
  }
  return false;
}

GroundSample HeightField::ground_sample(double x, double y) const {
  GroundSample best;
  if (!std::isfinite(x) || !std::isfinite(y)) return best;  // no comparison with NaN (it traps)
  bool inside = false;
  for (const Feature& f : features_) {
    if (x < f.xmin || x > f.xmax || y < f.ymin || y > f.ymax) continue;
    const double dx = x - f.cx, dy = y - f.cy;
    const double u = f.c * dx + f.s * dy;
    const double v = -f.s * dx + f.c * dy;
    if (std::abs(u) > f.hu || std::abs(v) > f.hv) continue;
    double z = f.z, dzdu = 0.0;
    if (f.type == TerrainType::Ramp && !profile(f, u, z, dzdu)) continue;
    if (!inside || z > best.z_m) {
      // d/du rotated back to the world: (dz/dx, dz/dy) = dzdu * (cos yaw, sin yaw).
      best = {z, dzdu * f.c, dzdu * f.s};
      inside = true;
    }
  }
  return best;
}

double HeightField::height_at(double x, double y) const {
  double z = ground_at(x, y);
  if (!std::isfinite(x) || !std::isfinite(y)) return z;
  for (const Top& p : tops_) {
    if (p.z_top <= z) continue;
    const double dx = x - p.cx, dy = y - p.cy;
    const bool in =
        p.box ? std::abs(p.c * dx + p.s * dy) <= p.hx && std::abs(-p.s * dx + p.c * dy) <= p.hy
              : dx * dx + dy * dy <= p.r * p.r;
    if (in) z = p.z_top;
  }
  return z;
}

}  // namespace carril::sim
