#pragma once
// The obstacle-ahead question the runner's stop and the missions share, answered at most once
// per tick, and the lidar's returns the missions' own body checks can add to their costmaps.
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mission/SafetyFields.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"

namespace carril::fw {

struct ObstacleStopConfig {
  // A standing obstacle this close ahead of the bumper stops the robot once it is at rest: the
  // stop starts stop_m plus the stopping distance from the speed it drives at (the protective
  // fields' stop(v) - C) short of it, so the robot comes to rest about stop_m short at any speed
  // (at rest it is stop_m) [m].
  double stop_m = 0.45;
  double corridor_margin_m = 0.10;  // the corridor ahead: robot width + this each side [m]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<ObstacleStopConfig>> params();
  Status validate() const;
  bool operator==(const ObstacleStopConfig&) const = default;
};

// The obstacle-ahead question, answered at most once per tick (the missions and the runner's
// own stop share the answer).
class ObstacleGuard {
 public:
  ObstacleGuard(const ObstacleStopConfig& cfg, const SafetyFieldsConfig& fields,
                const Topic<ObstacleField>& obstacles, const Topic<OdometryMsg>& odom)
      : cfg_(cfg), fields_(fields), obstacles_(obstacles), odom_(odom) {}

  void new_tick() { known_ = false; }
  // A standing obstacle ahead, within the distance the robot needs to come to rest stop_m short
  // of it (returns marked moving are the protective fields' business: the robot waits for them).
  bool ahead() const;
  // That distance at the measured speed [m].
  double trigger_m() const;
  const ObstacleStopConfig& config() const { return cfg_; }
  // The lidar's returns (odometry frame, with those it remembers from its blind sector) and the
  // odometry pose they are relative to: what the missions' own body checks can add to a map-frame
  // costmap whose marks a relocalisation has just cleared.
  const ObstacleField& field() const { return obstacles_.get(); }
  const Pose2& odom_pose() const { return odom_.get().pose; }

 private:
  ObstacleStopConfig cfg_;
  SafetyFieldsConfig fields_;
  const Topic<ObstacleField>& obstacles_;
  const Topic<OdometryMsg>& odom_;
  mutable bool known_ = false, ahead_ = false;
};

}  // namespace carril::fw
