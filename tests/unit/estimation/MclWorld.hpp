#pragma once
// A synthetic world for the Monte Carlo localisation tests and benchmark: a 10 x 8 m house-like
// floor plan at 0.05 m (four rooms, a hall, doors at different places, furniture, one unknown
// closet: no symmetry), exact grid ray casting, lidar scans with noise and drop-outs, and a robot
// that drives a tour through every room with drifting odometry.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "firmware/core/Geometry.hpp"
#include "firmware/estimation/MclRandom.hpp"
#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "hal/Types.hpp"

namespace carril::test::mcl {

using fw::Pose2;
namespace cost = fw::cost;

constexpr double kRes = 0.05;
constexpr int kNx = 200, kNy = 160;  // 10 x 8 m

// Cells whose centres lie in [x0, x1] x [y0, y1] [m] get value v.
inline void fill(std::vector<std::uint8_t>& c, int nx, int ny, double x0, double y0, double x1,
                 double y1, std::uint8_t v) {
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) * kRes, y = (j + 0.5) * kRes;
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) c[std::size_t(j * nx + i)] = v;
    }
  }
}

// The house's cells, row-major from the lower-left one.
inline std::vector<std::uint8_t> house_cells() {
  std::vector<std::uint8_t> c(std::size_t(kNx * kNy), cost::kFree);
  const auto wall = [&](double x0, double y0, double x1, double y1) {
    fill(c, kNx, kNy, x0, y0, x1, y1, cost::kLethal);
  };
  const auto door = [&](double x0, double y0, double x1, double y1) {
    fill(c, kNx, kNy, x0, y0, x1, y1, cost::kFree);
  };
  // Outer walls, 0.1 m.
  wall(0.0, 0.0, 10.0, 0.1);
  wall(0.0, 7.9, 10.0, 8.0);
  wall(0.0, 0.0, 0.1, 8.0);
  wall(9.9, 0.0, 10.0, 8.0);
  // Living room (0..6 x 0..4.5) | bedroom 1 and hall above it.
  wall(0.0, 4.45, 6.0, 4.55);
  door(1.2, 4.4, 2.1, 4.6);  // living -> bedroom 1
  door(4.6, 4.4, 5.5, 4.6);  // living -> hall
  // Bedroom 1 (0..4 x 4.5..8) | hall (4..6).
  wall(3.95, 4.5, 4.05, 8.0);
  door(3.9, 6.8, 4.1, 7.6);
  // Living and hall | kitchen and bedroom 2 (6..10).
  wall(5.95, 0.0, 6.05, 8.0);
  door(5.9, 1.0, 6.1, 1.9);  // living -> kitchen
  door(5.9, 5.8, 6.1, 6.7);  // hall -> bedroom 2
  // Kitchen (6..10 x 0..3) | bedroom 2 (6..10 x 3..8).
  wall(6.0, 2.95, 10.0, 3.05);
  door(8.6, 2.9, 9.5, 3.1);
  // Furniture.
  wall(0.3, 0.2, 2.3, 1.0);  // sofa
  wall(2.8, 2.2, 3.8, 3.0);  // table
  wall(5.0, 0.8, 5.3, 1.1);  // column
  wall(6.1, 0.1, 9.9, 0.7);  // kitchen counter
  wall(7.5, 1.6, 8.5, 2.1);  // kitchen island
  wall(0.1, 5.5, 1.6, 7.9);  // bed 1
  wall(3.3, 4.6, 3.9, 5.6);  // wardrobe
  wall(4.1, 5.0, 4.4, 5.8);  // shelf in the hall
  wall(8.2, 5.8, 9.9, 7.9);  // bed 2
  wall(6.1, 3.1, 7.2, 3.6);  // desk
  // A closet nobody surveyed: walls known, inside unknown.
  wall(6.05, 7.1, 7.0, 7.95);
  fill(c, kNx, kNy, 6.15, 7.2, 6.9, 7.85, cost::kUnknown);
  return c;
}

inline fw::OccupancyGrid make_house() {
  fw::OccupancyGrid g(std::size_t(kNx * kNy));
  fw::MapInfo info;
  info.nx = kNx;
  info.ny = kNy;
  info.resolution_m = kRes;
  const std::vector<std::uint8_t> c = house_cells();
  (void)g.assign(info, c.data());
  return g;
}

// Exact ray cast over the grid (Amanatides and Woo): distance [m] from (x, y) along `angle` to
// where the ray enters the first occupied cell, +inf if none within max_range or the ray leaves
// the map first.
inline double cast_ray(const fw::OccupancyGrid& g, double x, double y, double angle,
                       double max_range) {
  const double res = g.resolution();
  const double ox = g.info().origin_x_m, oy = g.info().origin_y_m;
  const double dx = std::cos(angle), dy = std::sin(angle);
  double fx = (x - ox) / res, fy = (y - oy) / res;
  int i = int(std::floor(fx)), j = int(std::floor(fy));
  const int si = dx > 0 ? 1 : -1, sj = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double tdx = dx != 0.0 ? res / std::abs(dx) : inf;
  const double tdy = dy != 0.0 ? res / std::abs(dy) : inf;
  double tx = dx != 0.0 ? ((dx > 0 ? (i + 1 - fx) : (fx - i)) * res) / std::abs(dx) : inf;
  double ty = dy != 0.0 ? ((dy > 0 ? (j + 1 - fy) : (fy - j)) * res) / std::abs(dy) : inf;
  double t = 0.0;
  while (t <= max_range) {
    if (!g.contains(i, j)) return inf;
    if (g.at(i, j) == cost::kLethal) return t;
    if (tx < ty) {
      t = tx;
      tx += tdx;
      i += si;
    } else {
      t = ty;
      ty += tdy;
      j += sj;
    }
  }
  return inf;
}

struct ScanSpec {
  int beams = 360;            // over 360 deg
  double range_max_m = 10.0;  // [m]
  double noise_m = 0.01;      // Gaussian range noise [m]
  double dropout = 0.02;      // probability of a NaN return
  double clutter = 0.02;      // probability of a short random return (a person, a chair)
};

// A scan from the lidar at `mount` on a robot at `robot` (map frame).
inline void synth_scan(const fw::OccupancyGrid& g, const Pose2& robot, const Pose2& mount,
                       const ScanSpec& spec, fw::MclRng& rng, hal::LaserScan& out) {
  const fw::Vec2 l = fw::to_world(robot, fw::Vec2(mount.x, mount.y));
  const double yaw = robot.yaw + mount.yaw;
  out.seq += 1;
  out.count = std::uint16_t(spec.beams);
  out.angle_min_rad = float(-fw::kPi);
  out.angle_increment_rad = float(2.0 * fw::kPi / spec.beams);
  out.range_min_m = 0.05F;
  out.range_max_m = float(spec.range_max_m);
  for (int k = 0; k < spec.beams; ++k) {
    const double a = double(out.angle_min_rad) + k * double(out.angle_increment_rad);
    double r = cast_ray(g, l.x(), l.y(), yaw + a, spec.range_max_m);
    if (std::isfinite(r)) r += rng.gaussian(spec.noise_m);
    const double u = rng.uniform();
    if (u < spec.dropout) {
      r = std::numeric_limits<double>::quiet_NaN();
    } else if (u < spec.dropout + spec.clutter && std::isfinite(r)) {
      r = rng.uniform(0.1, r);
    }
    out.ranges_m[std::size_t(k)] = std::isfinite(r)
                                       ? float(std::min(r, spec.range_max_m + 1.0))
                                       : (std::isnan(r) ? std::numeric_limits<float>::quiet_NaN()
                                                        : std::numeric_limits<float>::infinity());
  }
}

// Waypoints of a tour through every room and door (map frame [m]), ending where it starts.
inline std::vector<fw::Vec2> house_tour() {
  return {{1.5, 3.5},   {4.5, 3.6},  {5.05, 3.8}, {5.05, 6.25}, {6.9, 6.25}, {7.6, 4.8},
          {9.05, 4.2},  {9.05, 2.5}, {8.9, 1.3},  {7.0, 1.3},   {4.5, 1.45}, {3.2, 1.6},
          {1.65, 1.7},  {1.65, 3.5}, {1.65, 5.1}, {2.6, 6.3},   {3.4, 7.2},  {4.8, 7.2},
          {5.05, 6.25}, {5.05, 3.8}, {1.5, 3.5}};
}

// A robot driving the tour: turns in place towards the next waypoint, then drives straight.
// Odometry integrates the true motion with a 3 % scale error, a yaw bias and noise, so it drifts.
class TourDriver {
 public:
  TourDriver(std::vector<fw::Vec2> tour, std::uint64_t seed, std::size_t first = 1)
      : tour_(std::move(tour)), next_(first), rng_(seed) {
    truth_ = {tour_[first - 1].x(), tour_[first - 1].y(), 0.0};
    const fw::Vec2 d = tour_[first] - tour_[first - 1];
    truth_.yaw = std::atan2(d.y(), d.x());
  }

  // One control period: up to step_m forward or turn_rad of turn.
  void step(double step_m = 0.05, double turn_rad = 0.1) {
    const fw::Vec2 target = tour_[next_];
    const fw::Vec2 d = target - fw::Vec2(truth_.x, truth_.y);
    double fwd = 0.0, turn = 0.0;
    if (d.norm() < 1e-3) {
      next_ = next_ + 1 < tour_.size() ? next_ + 1 : 1;
      return;
    }
    const double err = fw::wrap_angle(std::atan2(d.y(), d.x()) - truth_.yaw);
    if (std::abs(err) > 0.02) {
      turn = fw::clampd(err, -turn_rad, turn_rad);
    } else {
      turn = err;
      fwd = std::min(step_m, d.norm());
    }
    move(truth_, fwd, turn);
    move(odom_, fwd * 1.03 + rng_.gaussian(0.002),
         turn * 0.98 + 0.002 * fwd + rng_.gaussian(0.002));
  }

  // Teleports the true robot (the odometry does not see it).
  void kidnap(const Pose2& to, std::size_t next_waypoint) {
    truth_ = to;
    next_ = next_waypoint;
  }

  const Pose2& truth() const { return truth_; }
  const Pose2& odom() const { return odom_; }
  std::size_t next_waypoint() const { return next_; }

 private:
  static void move(Pose2& p, double fwd, double turn) {
    p.yaw = fw::wrap_angle(p.yaw + turn);
    p.x += fwd * std::cos(p.yaw);
    p.y += fwd * std::sin(p.yaw);
  }

  std::vector<fw::Vec2> tour_;
  std::size_t next_;
  fw::MclRng rng_;
  Pose2 truth_;
  Pose2 odom_;  // starts at the odometry origin
};

}  // namespace carril::test::mcl
