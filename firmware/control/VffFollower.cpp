#include "firmware/control/VffFollower.hpp"

#include <cmath>

#include "firmware/control/PurePursuitFollower.hpp"
#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

Status VffConfig::validate() const {
  return Checks("vff")
      .range("carrot_lookahead_m", carrot_lookahead_m, 0.05, 10.0, "m")
      .range("attraction_gain", attraction_gain, 0.01, 100.0, "")
      .range("repulsion_gain", repulsion_gain, 0.0, 100.0, "")
      .range("repulsion_radius_m", repulsion_radius_m, 0.0, 5.0, "m")
      .range("repulsion_scale_m", repulsion_scale_m, 0.01, 5.0, "m")
      .range("max_repulsion_ratio", max_repulsion_ratio, 0.0, 0.99, "")
      .range("cost_threshold", cost_threshold, 1.0, double(cost::kLethal), "cost")
      .range("cruise_speed_mps", cruise_speed_mps, 0.01, 5.0, "m/s")
      .range("min_speed_mps", min_speed_mps, 0.0, cruise_speed_mps, "m/s")
      .range("slow_radius_m", slow_radius_m, 0.0, 10.0, "m")
      .range("max_yaw_rate_radps", max_yaw_rate_radps, 0.05, 10.0, "rad/s")
      .range("turn_gain", turn_gain, 0.1, 20.0, "1/s")
      .range("turn_in_place_rad", turn_in_place_rad, 0.05, kPi, "rad")
      .range("goal_tolerance_m", goal_tolerance_m, 0.001, 2.0, "m")
      .result();
}

void VffFollower::reset() {
  progress_ = 0;
  at_end_ = false;
  attraction_ = repulsion_ = Vec2{0.0, 0.0};
}

// Sum of the pushes of the cells within repulsion_radius of p (world frame).
Vec2 VffFollower::repulsion_at(const Vec2& p, const RollingGrid<std::uint8_t>& costmap) const {
  Vec2 f{0.0, 0.0};
  const double radius = cfg_.repulsion_radius_m;
  if (!costmap.ready() || !(radius > 0.0) || !(cfg_.repulsion_gain > 0.0)) return f;
  const int x0 = costmap.cell_of(p.x() - radius), x1 = costmap.cell_of(p.x() + radius);
  const int y0 = costmap.cell_of(p.y() - radius), y1 = costmap.cell_of(p.y() + radius);
  const double r2 = radius * radius;
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      if (!costmap.contains(cx, cy)) continue;
      const std::uint8_t c = costmap.at(cx, cy);
      if (c == cost::kUnknown ? !cfg_.unknown_repels : int(c) < cfg_.cost_threshold) continue;
      const Vec2 away{p.x() - costmap.center_of(cx), p.y() - costmap.center_of(cy)};
      const double d2 = away.squaredNorm();
      if (d2 > r2 || d2 < 1e-12) continue;  // on the robot's own point: no direction
      const double d = std::sqrt(d2);
      const double weight = double(c == cost::kUnknown ? cost::kLethal : c) / double(cost::kLethal);
      f += (cfg_.repulsion_gain * weight * std::exp(-d / cfg_.repulsion_scale_m) / d) * away;
    }
  }
  return f;
}

Twist VffFollower::update(const Pose2& pose, const Vec2* path, std::size_t n,
                          const RollingGrid<std::uint8_t>& costmap) {
  Twist t;
  if (n == 0 || path == nullptr || !std::isfinite(pose.x) || !std::isfinite(pose.y) ||
      !std::isfinite(pose.yaw))
    return t;
  const Vec2 p{pose.x, pose.y};
  const PathProjection proj = project_on_path(path, n, p, progress_, 64);
  progress_ = proj.segment;
  const double to_end = (path[n - 1] - p).norm();
  if (to_end < cfg_.goal_tolerance_m) at_end_ = true;
  if (at_end_) {
    attraction_ = repulsion_ = Vec2{0.0, 0.0};
    return t;
  }
  carrot_ = point_ahead(path, n, proj, cfg_.carrot_lookahead_m);
  const Vec2 to_carrot = carrot_ - p;
  const double dc = to_carrot.norm();
  attraction_ = dc > 1e-9 ? Vec2(cfg_.attraction_gain / dc * to_carrot) : Vec2(0.0, 0.0);
  repulsion_ = repulsion_at(p, costmap);
  const double cap = cfg_.max_repulsion_ratio * attraction_.norm();
  if (repulsion_.norm() > cap) repulsion_ *= cap / repulsion_.norm();
  const Vec2 f = attraction_ + repulsion_;
  if (f.squaredNorm() < 1e-12) return t;  // forces cancel: stop rather than guess

  const double err = wrap_angle(std::atan2(f.y(), f.x()) - pose.yaw);
  t.wz = clampd(cfg_.turn_gain * err, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
  if (std::fabs(err) > cfg_.turn_in_place_rad) return t;
  double v = cfg_.cruise_speed_mps;
  if (cfg_.slow_radius_m > 0.0)
    v = std::fmax(cfg_.min_speed_mps,
                  std::fmin(v, cfg_.cruise_speed_mps * to_end / cfg_.slow_radius_m));
  t.vx = v * std::cos(err);
  return t;
}

}  // namespace carril::fw
