#include "firmware/control/PursuitFollower.hpp"

#include <cmath>

namespace carril::fw {

Twist PursuitFollower::follow(const TapeObservation& obs) const {
  // Target: the tape point whose distance from the robot centre is closest to the look-ahead.
  Vec2 target = obs.line_points[0];
  double best = 1e9;
  for (const Vec2& p : obs.line_points) {
    const double e = std::fabs(p.norm() - lookahead_m_);
    if (e < best) {
      best = e;
      target = p;
    }
  }
  const double d2 = target.squaredNorm();
  const double curvature = d2 > 1e-6 ? 2.0 * target.y() / d2 : 0.0;
  const double v = speed_mps_ / (1.0 + cfg_.curvature_slowdown_m * std::fabs(curvature));
  return {v, 0.0, v * curvature};
}

Twist PursuitFollower::approach(const Vec2& target, bool holonomic) const {
  const double d = target.norm();
  const double v = std::fmin(speed_mps_, cfg_.end_approach_gain * d);
  if (d < 1e-9) return {};
  if (holonomic) return {v * target.x() / d, v * target.y() / d, 0.0};
  const double curvature = 2.0 * target.y() / (d * d);
  return {v, 0.0, v * curvature};
}

}  // namespace carril::fw
