#include "host_sim/sensors/Lidar3dSim.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace carril::sim {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kBisectTolM = 0.0005;  // crossing located to this along the beam [m]
}  // namespace

fw::Status Lidar3dConfig::validate() const {
  const loader::Lidar3dSpec& s = sensor;
  fw::Checks c("lidar3d");
  c.range("x_m", s.x_m, -5.0, 5.0, "m")
      .range("y_m", s.y_m, -5.0, 5.0, "m")
      .range("z_m", s.z_m, 0.05, 5.0, "m")
      .range("yaw_deg", s.yaw_deg, -360.0, 360.0, "deg")
      .range("rings", s.rings, 1, 128, "rings")
      .range("azimuths", s.azimuths, 1, hal::kMaxCloudPoints, "firings")
      .fail_if(s.rings * s.azimuths > hal::kMaxCloudPoints, "azimuths",
               "rings x azimuths exceeds hal::kMaxCloudPoints (65536)")
      .range("vertical_min_deg", s.vertical_min_deg, -90.0, 90.0, "deg")
      .range("vertical_max_deg", s.vertical_max_deg, -90.0, 90.0, "deg")
      .fail_if(s.rings > 1 && !(s.vertical_max_deg > s.vertical_min_deg), "vertical_max_deg",
               "must be above vertical_min_deg")
      .range("rate_hz", s.rate_hz, 1.0, 100.0, "Hz")
      .range("range_max_m", s.range_max_m, 0.5, 200.0, "m")
      .range("range_min_m", s.range_min_m, 0.0, 10.0, "m")
      .fail_if(!(s.range_min_m < s.range_max_m), "range_min_m", "must be below range_max_m")
      .range("noise_std_m", s.noise_std_m, 0.0, 1.0, "m")
      .range("drop_probability", s.drop_probability, 0.0, 1.0, "")
      .range("march_step_min_m", march_step_min_m, 0.001, 0.5, "m")
      .range("march_step_per_m", march_step_per_m, 0.0, 0.1, "m/m")
      .range("march_step_max_m", march_step_max_m, march_step_min_m, 1.0, "m");
  return c.result();
}

Lidar3dSim::Lidar3dSim(const Lidar3dConfig& cfg, std::uint64_t seed)
    : cfg_(cfg),
      period_ns_(static_cast<hal::TimeNs>(std::llround(1e9 / cfg.sensor.rate_hz))),
      rng_(seed ^ 0x3D11DA5ULL) {
  const loader::Lidar3dSpec& s = cfg_.sensor;
  sin_el_.resize(std::size_t(s.rings));
  cos_el_.resize(std::size_t(s.rings));
  for (int r = 0; r < s.rings; ++r) {
    sin_el_[std::size_t(r)] = std::sin(ring_elevation_rad(r));
    cos_el_[std::size_t(r)] = std::cos(ring_elevation_rad(r));
  }
  cos_az_.resize(std::size_t(s.azimuths));
  sin_az_.resize(std::size_t(s.azimuths));
  for (int a = 0; a < s.azimuths; ++a) {
    cos_az_[std::size_t(a)] = std::cos(azimuth_rad(a));
    sin_az_[std::size_t(a)] = std::sin(azimuth_rad(a));
  }
}

double Lidar3dSim::ring_elevation_rad(int r) const {
  const loader::Lidar3dSpec& s = cfg_.sensor;
  if (s.rings == 1) return s.vertical_min_deg * kDeg;
  return (s.vertical_min_deg + (s.vertical_max_deg - s.vertical_min_deg) * r / (s.rings - 1)) *
         kDeg;
}

double Lidar3dSim::azimuth_rad(int a) const {
  return 2.0 * std::numbers::pi * a / cfg_.sensor.azimuths;
}

double Lidar3dSim::cast(const HeightQuery& world, double ox, double oy, double oz, double dx,
                        double dy, double dz, double max_h, double min_h) {
  // The part of the beam that can meet the surface: below max_h, and no farther than where it
  // passes min_h (there it is surely below the surface) or range_max_m.
  double t = 0.0;
  double t_end = cfg_.sensor.range_max_m;
  if (dz > 0.0) {
    if (oz >= max_h) return -1.0;  // rising above everything
    t_end = std::min(t_end, (max_h - oz) / dz);
  } else if (dz < 0.0) {
    if (oz > max_h) t = (oz - max_h) / -dz;
    // 1 mm under min_h, so a beam onto a surface at min_h (a flat floor) meets it before t_end.
    t_end = std::min(t_end, (oz - min_h + 0.001) / -dz);
  } else if (oz >= max_h) {
    return -1.0;
  }
  if (t > t_end) return -1.0;
  auto below = [&](double tt) {
    ++queries_;
    return std::isless(oz + dz * tt, world.height_at(ox + dx * tt, oy + dy * tt));
  };
  if (below(t)) return t;  // starts inside the surface (sensor buried): an immediate return
  const double k = cfg_.march_step_per_m, s_min = cfg_.march_step_min_m,
               s_max = cfg_.march_step_max_m;
  while (t < t_end) {
    const double step = std::clamp(t * k, s_min, s_max);
    const double t_next = std::min(t + step, t_end);
    if (below(t_next)) {
      // Above at t, below at t_next: bisect the crossing.
      double lo = t, hi = t_next;
      while (hi - lo > kBisectTolM) {
        const double mid = 0.5 * (lo + hi);
        if (below(mid)) {
          hi = mid;
        } else {
          lo = mid;
        }
      }
      return 0.5 * (lo + hi);
    }
    t = t_next;
  }
  return -1.0;
}

void Lidar3dSim::render(const HeightQuery& world, const BodyPose3& b, hal::TimeNs stamp_ns,
                        hal::PointCloud& out) {
  const loader::Lidar3dSpec& s = cfg_.sensor;
  queries_ = 0;
  // Body rotation R = Rz(yaw) Ry(pitch) Rx(roll), columns are the body axes in the world.
  const double cr = std::cos(b.roll_rad), sr = std::sin(b.roll_rad);
  const double cp = std::cos(b.pitch_rad), sp = std::sin(b.pitch_rad);
  const double cy = std::cos(b.yaw_rad), sy = std::sin(b.yaw_rad);
  const double R[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                          {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                          {-sp, cp * sr, cp * cr}};
  const double ox = b.x_m + R[0][0] * s.x_m + R[0][1] * s.y_m + R[0][2] * s.z_m;
  const double oy = b.y_m + R[1][0] * s.x_m + R[1][1] * s.y_m + R[1][2] * s.z_m;
  const double oz = b.z_m + R[2][0] * s.x_m + R[2][1] * s.y_m + R[2][2] * s.z_m;
  // Sensor axes in the world: the body's rotated by the mount yaw about body z.
  const double cm = std::cos(s.yaw_deg * kDeg), sm = std::sin(s.yaw_deg * kDeg);
  double S[3][3];
  for (int i = 0; i < 3; ++i) {
    S[i][0] = R[i][0] * cm + R[i][1] * sm;
    S[i][1] = -R[i][0] * sm + R[i][1] * cm;
    S[i][2] = R[i][2];
  }
  const double max_h = world.max_height(), min_h = world.min_height();
  const double p_drop = s.drop_probability;
  const double sigma = s.noise_std_m;
  std::uint32_t n = 0;
  for (int a = 0; a < s.azimuths; ++a) {
    const double ca = cos_az_[std::size_t(a)], sa = sin_az_[std::size_t(a)];
    for (int r = 0; r < s.rings; ++r) {
      if (p_drop > 0.0 && uniform_(rng_) < p_drop) continue;  // beam lost
      const double ce = cos_el_[std::size_t(r)], se = sin_el_[std::size_t(r)];
      const double ux = ce * ca, uy = ce * sa, uz = se;  // sensor frame
      const double dx = S[0][0] * ux + S[0][1] * uy + S[0][2] * uz;
      const double dy = S[1][0] * ux + S[1][1] * uy + S[1][2] * uz;
      const double dz = S[2][0] * ux + S[2][1] * uy + S[2][2] * uz;
      double range = cast(world, ox, oy, oz, dx, dy, dz, max_h, min_h);
      if (range < 0.0) continue;  // no return
      if (sigma > 0.0) range += sigma * noise_(rng_);
      if (!(range >= s.range_min_m && range <= s.range_max_m)) continue;
      hal::CloudPoint& p = out.points[n++];
      p.x = static_cast<float>(range * ux);
      p.y = static_cast<float>(range * uy);
      p.z = static_cast<float>(range * uz);
    }
  }
  out.count = n;
  out.seq = ++seq_;
  out.stamp_ns = stamp_ns;
}

}  // namespace carril::sim
