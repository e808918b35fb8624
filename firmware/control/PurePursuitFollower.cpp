#include "firmware/control/PurePursuitFollower.hpp"

#include <cmath>

namespace carril::fw {

PathProjection project_on_path(const Vec2* path, std::size_t n, const Vec2& p, std::size_t from,
                               std::size_t window) {
  PathProjection best;
  if (n == 0) return best;
  if (n == 1) {
    best.point = path[0];
    best.distance_m = (p - path[0]).norm();
    return best;
  }
  if (from > n - 2) from = n - 2;
  const std::size_t end = (window > n - 1 - from) ? n - 1 : from + window;
  best.distance_m = -1.0;
  for (std::size_t i = from; i < end; ++i) {
    const Vec2 a = path[i], d = path[i + 1] - path[i];
    const double len2 = d.squaredNorm();
    const double t = len2 > 1e-18 ? clampd((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    const Vec2 q = a + t * d;
    const double dist = (p - q).norm();
    if (best.distance_m < 0.0 || dist < best.distance_m) {
      best.segment = i;
      best.point = q;
      best.distance_m = dist;
    }
  }
  return best;
}

Vec2 point_ahead(const Vec2* path, std::size_t n, const PathProjection& from, double ahead_m) {
  if (n == 0) return from.point;
  Vec2 at = from.point;
  double left = ahead_m;
  for (std::size_t i = from.segment + 1; i < n; ++i) {
    const double len = (path[i] - at).norm();
    if (len >= left && len > 0.0) return at + (path[i] - at) * (left / len);
    left -= len;
    at = path[i];
  }
  return path[n - 1];
}

Status PurePursuitConfig::validate() const {
  return Checks("pure_pursuit")
      .range("lookahead_m", lookahead_m, 0.05, 10.0, "m")
      .range("cruise_speed_mps", cruise_speed_mps, 0.01, 5.0, "m/s")
      .range("min_speed_mps", min_speed_mps, 0.0, cruise_speed_mps, "m/s")
      .range("max_yaw_rate_radps", max_yaw_rate_radps, 0.05, 10.0, "rad/s")
      .range("max_lateral_accel_mps2", max_lateral_accel_mps2, 0.01, 20.0, "m/s^2")
      .range("slow_radius_m", slow_radius_m, 0.0, 10.0, "m")
      .range("goal_tolerance_m", goal_tolerance_m, 0.001, 2.0, "m")
      .range("rotate_in_place_rad", rotate_in_place_rad, 0.1, kPi, "rad")
      .range("turn_gain", turn_gain, 0.1, 20.0, "1/s")
      .result();
}

void PurePursuitFollower::reset() {
  progress_ = 0;
  at_end_ = false;
  cross_track_ = 0.0;
}

Twist PurePursuitFollower::update(const Pose2& pose, const Vec2* path, std::size_t n) {
  Twist t;
  if (n == 0 || path == nullptr || !std::isfinite(pose.x) || !std::isfinite(pose.y) ||
      !std::isfinite(pose.yaw))
    return t;
  const Vec2 p{pose.x, pose.y};
  // A window of segments ahead keeps the search bounded and the progress from jumping to a
  // later pass of a path that loops back near itself.
  const PathProjection proj = project_on_path(path, n, p, progress_, 64);
  progress_ = proj.segment;
  cross_track_ = proj.distance_m;
  const double to_end = (path[n - 1] - p).norm();
  if (to_end < cfg_.goal_tolerance_m) at_end_ = true;
  if (at_end_) return t;

  target_ = point_ahead(path, n, proj, cfg_.lookahead_m);
  const Vec2 r = to_robot(pose, target_);
  const double l2 = r.squaredNorm();
  if (l2 < 1e-12) return t;
  const double alpha = std::atan2(r.y(), r.x());
  if (std::fabs(alpha) > cfg_.rotate_in_place_rad) {
    t.wz = clampd(cfg_.turn_gain * alpha, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
    return t;
  }
  const double k = 2.0 * r.y() / l2;  // curvature of the arc through the pursued point [1/m]
  double v = cfg_.cruise_speed_mps;
  if (std::fabs(k) > 1e-9) v = std::fmin(v, std::sqrt(cfg_.max_lateral_accel_mps2 / std::fabs(k)));
  if (cfg_.slow_radius_m > 0.0)
    v = std::fmin(v, cfg_.cruise_speed_mps * to_end / cfg_.slow_radius_m);
  v = std::fmax(v, cfg_.min_speed_mps);
  double wz = v * k;
  if (std::fabs(wz) > cfg_.max_yaw_rate_radps) {
    // Keep the arc, drive it slower.
    v = cfg_.max_yaw_rate_radps / std::fabs(k);
    wz = std::copysign(cfg_.max_yaw_rate_radps, k);
  }
  t.vx = v;
  t.wz = wz;
  return t;
}

}  // namespace carril::fw
