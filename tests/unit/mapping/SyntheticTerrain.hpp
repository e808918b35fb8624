#pragma once
// Test helpers for the terrain tests: analytic surfaces, a simple ray-marched 3D lidar over them
// (an HDL-32E-like pattern: rings evenly spaced over [vmin, vmax], azimuths over 360 deg) and a
// direct fill of an elevation grid from a surface.
#include <cmath>
#include <functional>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/mapping/ElevationCell.hpp"
#include "firmware/mapping/Pose3Tracker.hpp"
#include "hal/PointCloud.hpp"

namespace carril::fw::synth {

using Surface = std::function<double(double x, double y)>;  // ground height [m]

inline double deg(double d) {
  return d * kPi / 180.0;
}

// Flat ground, then a ramp of angle_deg rising along +x from x0 for `length` m, then a plateau.
inline Surface ramp(double x0, double length, double angle_deg) {
  const double t = std::tan(deg(angle_deg));
  return [=](double x, double) { return x < x0 ? 0.0 : (x < x0 + length ? x - x0 : length) * t; };
}

// A step of `height` m (negative: a drop) along +x at x0.
inline Surface step(double x0, double height) {
  return [=](double x, double) { return x < x0 ? 0.0 : height; };
}

// A box of side `side` and height `height` centred at (cx, cy) on flat ground.
inline Surface box(double cx, double cy, double side, double height) {
  return [=](double x, double y) {
    return std::fabs(x - cx) < 0.5 * side && std::fabs(y - cy) < 0.5 * side ? height : 0.0;
  };
}

struct LidarPattern {
  int rings = 32;
  int azimuths = 1800;
  double vmin_deg = -30.67, vmax_deg = 10.67;
  double range_max = 12.0;
  double step_m = 0.01;  // march step
};

// Ray-marches every beam from `sensor` (odometry frame) against `surface` (max height
// `top` [m]) and writes the hits into `out` in the SENSOR frame. Returns the point count.
inline std::uint32_t render(const Surface& surface, double top, const Pose3& sensor,
                            const LidarPattern& pat, hal::PointCloud& out) {
  const Mat3 r = rotation_of(sensor.roll, sensor.pitch, sensor.yaw);
  const Vec3 t(sensor.x, sensor.y, sensor.z);
  std::uint32_t n = 0;
  for (int ring = 0; ring < pat.rings; ++ring) {
    const double el = deg(pat.vmin_deg + (pat.vmax_deg - pat.vmin_deg) * ring / (pat.rings - 1));
    for (int a = 0; a < pat.azimuths && n < std::uint32_t(hal::kMaxCloudPoints); ++a) {
      const double az = 2.0 * kPi * a / pat.azimuths;
      const Vec3 ds(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const Vec3 dw = r * ds;
      double prev = 0.0;
      for (double s = pat.step_m; s <= pat.range_max; s += pat.step_m) {
        const Vec3 p = t + s * dw;
        if (p.z() > top && dw.z() >= 0.0) break;
        if (p.z() <= surface(p.x(), p.y())) {
          double lo = prev, hi = s;  // refine the crossing
          for (int it = 0; it < 20; ++it) {
            const double m = 0.5 * (lo + hi);
            const Vec3 q = t + m * dw;
            (q.z() <= surface(q.x(), q.y()) ? hi : lo) = m;
          }
          const Vec3 ps = hi * ds;
          out.points[n++] = hal::CloudPoint{float(ps.x()), float(ps.y()), float(ps.z())};
          break;
        }
        prev = s;
      }
    }
  }
  out.count = n;
  out.seq += 1;
  return n;
}

// Sets every cell of the window to the surface height at its centre, with variance `var`.
inline void fill(RollingGrid<ElevationCell>& g, const Surface& surface, float var = 1e-4F) {
  for (int ly = 0; ly < g.ny(); ++ly)
    for (int lx = 0; lx < g.nx(); ++lx) {
      const int cx = g.origin_cx() + lx, cy = g.origin_cy() + ly;
      g.at(cx, cy) = ElevationCell{float(surface(g.center_of(cx), g.center_of(cy))), var};
    }
}

}  // namespace carril::fw::synth
