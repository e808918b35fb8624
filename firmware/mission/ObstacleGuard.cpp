#include "firmware/mission/ObstacleGuard.hpp"

#include "firmware/core/Param.hpp"

#include <cmath>

#include "firmware/mission/Mission.hpp"

namespace carril::fw {

std::span<const Param<ObstacleStopConfig>> ObstacleStopConfig::params() {
  using C = ObstacleStopConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, stop_m, "m", 0.05, 5.0,
                   "a standing obstacle ahead brings the robot to rest about this far short of it "
                   "(and starts AVOID): the stop begins `stop_m` plus the stopping distance from "
                   "its speed (`stop(v)` - C, below) short of it"),
      CARRIL_PARAM(C, corridor_margin_m, "m", 0.0, 1.0,
                   "the corridor ahead: robot width + this each side"),
  };
  return kParams;
}

Status ObstacleStopConfig::validate() const {
  return Checks("runner.obstacle").params(*this, params()).result();
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
