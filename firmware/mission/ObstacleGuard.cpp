#include "firmware/mission/ObstacleGuard.hpp"

#include <cmath>

#include "firmware/mission/Mission.hpp"

namespace carril::fw {

Status ObstacleStopConfig::validate() const {
  return Checks("runner.obstacle")
      .range("stop_m", stop_m, 0.05, 5.0, "m")
      .range("corridor_margin_m", corridor_margin_m, 0.0, 1.0, "m")
      .result();
}

double ObstacleGuard::trigger_m() const {
  const Twist& t = odom_.get().twist;
  const double v = std::hypot(t.vx, t.vy);
  return cfg_.stop_m + (fields_.enabled ? fields_.stop_m(v) - fields_.margin_m : 0.0);
}

bool ObstacleGuard::ahead() const {
  if (!known_) {
    const ObstacleField& f = obstacles_.get();
    const double reach = trigger_m();
    ahead_ = f.valid() && f.ahead_m(odom_.get().pose, cfg_.corridor_margin_m, reach + 1.0,
                                    fields_.enabled) < reach;
    known_ = true;
  }
  return ahead_;
}

bool MissionContext::obstacle_ahead() const {
  return guard != nullptr && guard->ahead();
}

}  // namespace carril::fw
