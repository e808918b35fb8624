#include "firmware/control/PathTracker.hpp"

#include <cmath>

namespace carril::fw {

Status PathTrackerConfig::validate() const {
  return Checks("path")
      .range("turn_gain", turn_gain, 0.1, 20.0, "1/s")
      .range("max_turn_rate_radps", max_turn_rate_radps, 0.01, 10.0, "rad/s")
      .range("reached_m", reached_m, 0.001, 1.0, "m")
      .result();
}

Twist PathTracker::turn_to(const Pose2& odom, double target) const {
  const double e = wrap_angle(target - odom.yaw);
  return {0.0, 0.0,
          clampd(cfg_.turn_gain * e, -cfg_.max_turn_rate_radps, cfg_.max_turn_rate_radps)};
}

Twist PathTracker::drive_to(const Pose2& odom, const Vec2& wp, double hold_heading, double speed,
                            bool& reached) const {
  const Vec2 e = to_robot(odom, wp);
  const double d = e.norm();
  reached = d < cfg_.reached_m;
  Twist t;
  if (reached) return t;
  const double v = speed * std::fmin(1.0, d / 0.3) + 0.03;
  if (holonomic_) {
    t.vx = v * e.x() / d;
    t.vy = v * e.y() / d;
    t.wz = clampd(2.0 * wrap_angle(hold_heading - odom.yaw), -0.8, 0.8);
    return t;
  }
  const double bearing = std::atan2(e.y(), e.x());
  if (std::fabs(bearing) > 0.15) {
    t.wz = clampd(2.5 * bearing, -1.0, 1.0);  // turn on the spot first
  } else {
    t.vx = v;
    t.wz = 2.0 * bearing;
  }
  return t;
}

Twist PathTracker::follow(const Pose2& odom, const Vec2* waypoints, std::size_t n,
                          std::size_t& index, double hold_heading, double speed_mps,
                          bool& done) const {
  done = index >= n;
  if (done) return {};
  bool reached = false;
  const Twist t = drive_to(odom, waypoints[index], hold_heading, speed_mps, reached);
  if (reached) {
    ++index;
    done = index >= n;
  }
  return t;
}

Twist PathTracker::approach(const Pose2& odom, const Vec2& goal, double max_speed_mps, double gain,
                            double tolerance_m, bool& arrived) const {
  const Vec2 e = to_robot(odom, goal);
  const double d = e.norm();
  arrived = d < tolerance_m || (!holonomic_ && e.x() <= 0.0 && d < 0.05);
  if (arrived) return {};
  const double v = std::fmin(max_speed_mps, gain * d);
  if (holonomic_) return {v * e.x() / d, v * e.y() / d, 0.0};
  const double bearing = std::atan2(e.y(), e.x());
  return {v * std::fmax(0.0, std::cos(bearing)), 0.0, clampd(2.0 * bearing, -0.8, 0.8)};
}

}  // namespace carril::fw
