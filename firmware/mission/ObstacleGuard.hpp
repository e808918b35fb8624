#pragma once
// The obstacle-ahead question the runner's stop and the missions share, answered at most once
// per tick, and the lidar's returns the missions' own body checks can add to their costmaps.
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/perception/ObstacleField.hpp"

namespace carril::fw {

struct ObstacleStopConfig {
  double stop_m = 0.45;             // an obstacle this close ahead of the bumper stops [m]
  double corridor_margin_m = 0.10;  // the corridor ahead: robot width + this each side [m]

  Status validate() const;
};

// The obstacle-ahead question, answered at most once per tick (the missions and the runner's
// own stop share the answer).
class ObstacleGuard {
 public:
  ObstacleGuard(const ObstacleStopConfig& cfg, const Topic<ObstacleField>& obstacles,
                const Topic<OdometryMsg>& odom)
      : cfg_(cfg), obstacles_(obstacles), odom_(odom) {}

  void new_tick() { known_ = false; }
  bool ahead() const;
  const ObstacleStopConfig& config() const { return cfg_; }
  // The lidar's returns (odometry frame, with those it remembers from its blind sector) and the
  // odometry pose they are relative to: what the missions' own body checks can add to a map-frame
  // costmap whose marks a relocalisation has just cleared.
  const ObstacleField& field() const { return obstacles_.get(); }
  const Pose2& odom_pose() const { return odom_.get().pose; }

 private:
  ObstacleStopConfig cfg_;
  const Topic<ObstacleField>& obstacles_;
  const Topic<OdometryMsg>& odom_;
  mutable bool known_ = false, ahead_ = false;
};

}  // namespace carril::fw
