#include "firmware/mission/ObstacleGuard.hpp"

#include "firmware/mission/Mission.hpp"

namespace carril::fw {

Status ObstacleStopConfig::validate() const {
  return Checks("runner.obstacle")
      .range("stop_m", stop_m, 0.05, 5.0, "m")
      .range("corridor_margin_m", corridor_margin_m, 0.0, 1.0, "m")
      .result();
}

bool ObstacleGuard::ahead() const {
  if (!known_) {
    const ObstacleField& f = obstacles_.get();
    ahead_ = f.valid() && f.ahead_m(odom_.get().pose, cfg_.corridor_margin_m, 5.0) < cfg_.stop_m;
    known_ = true;
  }
  return ahead_;
}

bool MissionContext::obstacle_ahead() const {
  return guard != nullptr && guard->ahead();
}

}  // namespace carril::fw
