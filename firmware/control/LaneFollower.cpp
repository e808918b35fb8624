#include "firmware/control/LaneFollower.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

Status LaneFollowerConfig::validate() const {
  return Checks("lane_follower")
      .range("cruise_speed_mps", cruise_speed_mps, 0.01, 5.0, "m/s")
      .range("min_speed_mps", min_speed_mps, 0.0, cruise_speed_mps, "m/s")
      .range("max_yaw_rate_radps", max_yaw_rate_radps, 0.05, 10.0, "rad/s")
      .range("decel_mps2", decel_mps2, 0.01, 20.0, "m/s^2")
      .range("heading_gain", heading_gain, 0.0, 100.0, "1/s")
      .range("cross_track_gain", cross_track_gain, 0.0, 10000.0, "1/m^2")
      .range("curvature_window_m", curvature_window_m, 0.005, 2.0, "m")
      .range("anticipation_m", anticipation_m, 0.0, 2.0, "m")
      .range("brake_lookahead_m", brake_lookahead_m, 0.0, 5.0, "m")
      .range("bend_window_m", bend_window_m, 0.005, 1.0, "m")
      .range("goal_tolerance_m", goal_tolerance_m, 0.001, 1.0, "m")
      .range("rotate_in_place_rad", rotate_in_place_rad, 0.1, 3.2, "rad")
      .range("max_yaw_accel_radps2", max_yaw_accel_radps2, 0.0, 100.0, "rad/s^2")
      .range("period_s", period_s, 0.001, 1.0, "s")
      .result();
}

void LaneFollower::reset() {
  progress_ = 0;
  at_end_ = false;
  wz_last_ = 0.0;
  cross_track_ = 0.0;
  curvature_ = 0.0;
}

namespace {
// The segment of path[0..n) holding the point `s` metres ahead of projection `at` and that
// point's heading; the last segment when the path ends sooner.
double heading_ahead(const Vec2* path, std::size_t n, const PathProjection& at, double s) {
  std::size_t i = at.segment;
  Vec2 a = at.point;
  for (; i + 1 < n; ++i) {
    const Vec2 b = path[i + 1];
    const double len = (b - a).norm();
    if (len >= s && (path[i + 1] - path[i]).norm() > 1e-9) break;
    s -= len;
    a = b;
  }
  // Heading of the segment reached (the last one with a length when the path ends first).
  std::size_t k = std::min(i, n >= 2 ? n - 2 : 0);
  while (k > 0 && (path[k + 1] - path[k]).norm() <= 1e-9) --k;
  const Vec2 d = path[k + 1] - path[k];
  return std::atan2(d.y(), d.x());
}
// On the last segment and across the line through its end square to it: the robot went by the
// end wider than goal_tolerance. Driving on would follow the lane's line past its end (into the
// wall a lane ends at), speeding up as the straight distance to the end grows.
bool past_end(const Vec2* path, std::size_t n, const PathProjection& at, const Vec2& p) {
  if (n < 2 || at.segment + 2 < n) return false;
  const Vec2 d = path[n - 1] - path[n - 2];
  return d.dot(p - path[n - 1]) >= 0.0 && d.squaredNorm() > 1e-18;
}
}  // namespace

double path_heading(const Vec2* path, std::size_t n, const PathProjection& at) {
  if (n < 2) return 0.0;
  return heading_ahead(path, n, at, 0.0);
}

double path_curvature(const Vec2* path, std::size_t n, const PathProjection& at, double s0,
                      double s1) {
  if (n < 3 || s1 <= s0) return 0.0;
  // The circle through three points of the path (Menger curvature): smooth along a polyline of
  // an arc, where counting the turns at its vertices would jump.
  const Vec2 a = point_ahead(path, n, at, s0);
  const Vec2 b = point_ahead(path, n, at, 0.5 * (s0 + s1));
  const Vec2 c = point_ahead(path, n, at, s1);
  const Vec2 ab = b - a, bc = c - b, ac = c - a;
  const double d = ab.norm() * bc.norm() * ac.norm();
  if (d < 1e-12) return 0.0;
  return 2.0 * (ab.x() * ac.y() - ab.y() * ac.x()) / d;
}

Twist LaneFollower::update(const Pose2& pose, const Vec2* path, std::size_t n) {
  const Twist t = command(pose, path, n);
  wz_last_ = t.wz;
  return t;
}

double LaneFollower::toward(double e) const {
  const double p = cfg_.heading_gain * e;
  if (cfg_.max_yaw_accel_radps2 <= 0.0) return p;
  // A robot still turning fast when the heading is reached swings past it, and runs sideways
  // into what the lane passes close by (a door's jamb).
  const double room = std::max(0.0, std::fabs(e) - std::fabs(wz_last_) * cfg_.period_s);
  const double w = std::min(std::fabs(p), std::sqrt(2.0 * cfg_.max_yaw_accel_radps2 * room));
  return e < 0.0 ? -w : w;
}

Twist LaneFollower::command(const Pose2& pose, const Vec2* path, std::size_t n) {
  Twist t;
  if (n == 0 || path == nullptr || !std::isfinite(pose.x) || !std::isfinite(pose.y) ||
      !std::isfinite(pose.yaw)) {
    return t;
  }
  const Vec2 p{pose.x, pose.y};
  // A short window: routes run back and forth close to themselves.
  PathProjection at = project_on_path(path, n, p, progress_, 8);
  // Past the end of a segment that turns sharply, the corner's vertex is the nearest point of both
  // segments, and the tie goes to the earlier one, whose heading leads on past the corner (a
  // short first segment onto a lane): the later one is the one to follow.
  if (at.segment + 2 < n && at.point.x() == path[at.segment + 1].x() &&
      at.point.y() == path[at.segment + 1].y()) {
    ++at.segment;
  }
  progress_ = at.segment;
  const double to_end = (path[n - 1] - p).norm();
  if (to_end < cfg_.goal_tolerance_m || n < 2 || past_end(path, n, at, p)) at_end_ = true;
  if (at_end_) return t;
  const double heading = path_heading(path, n, at);
  const Vec2 tangent(std::cos(heading), std::sin(heading));
  const Vec2 off = at.point - p;
  cross_track_ = tangent.x() * off.y() - tangent.y() * off.x();
  const double e_yaw = wrap_angle(heading - pose.yaw);
  if (std::fabs(e_yaw) > cfg_.rotate_in_place_rad) {
    t.wz = clampd(toward(e_yaw), -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
    return t;
  }
  const double a0 = cfg_.anticipation_m;
  curvature_ = path_curvature(path, n, at, a0, a0 + cfg_.curvature_window_m);
  // Slower the more the heading is off, so a late correction does not run the robot sideways.
  double v = cfg_.cruise_speed_mps * std::max(0.2, std::cos(2.0 * e_yaw));
  // Hold the path's curvature within the yaw-rate cap (a margin left for the feedback), here
  // and, braking in time, at the bends ahead (a tight one past a lane's end).
  const double step = cfg_.brake_lookahead_m / kBrakeSamples;
  for (int k = 0; k <= kBrakeSamples; ++k) {
    const double d = step * k;
    const double kd = k == 0 ? std::fabs(curvature_)
                             : std::fabs(path_curvature(path, n, at, d, d + cfg_.bend_window_m));
    if (kd < 1e-9) continue;
    const double vc = 0.85 * cfg_.max_yaw_rate_radps / kd;
    v = std::min(v, std::sqrt(vc * vc + 2.0 * cfg_.decel_mps2 * d));
  }
  // Brake toward the route's end (distance along it approximated by the straight distance).
  v = std::min(v, std::max(cfg_.min_speed_mps, std::sqrt(2.0 * cfg_.decel_mps2 * to_end)));
  const double wz = v * curvature_ + toward(e_yaw) + cfg_.cross_track_gain * v * cross_track_;
  t.vx = v;
  t.wz = clampd(wz, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
  return t;
}

}  // namespace carril::fw
