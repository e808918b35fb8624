#pragma once
// Component: where the robot is in the map frame. Without a map it passes odometry through (the
// map frame is then the odometry frame). On a known map it runs Monte Carlo localisation
// (firmware/estimation/MonteCarloLocalizer) on the 2D scans, spread over ticks with a particle
// budget per tick, and publishes every tick the odometry pose carried into the map frame by the
// newest correction (map <- odom, as AMCL's transform): smooth between scans, corrected at each
// completed update. The missions and the costmap read this pose.
#include <cstdint>

#include "firmware/core/Frames.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

struct LocalisationConfig {
  bool enabled = false;  // a static map is given: localise on it
  Pose2 initial_pose;    // the robot's start as the operator gives it, map frame [m, m, rad]

  Status validate() const;
};

struct LocalisationTelemetry {
  std::uint32_t updates = 0;  // completed measurement updates
  Pose2 pose;                 // the published pose, map frame [m, m, rad]
};

// Pose composition: a then b (b expressed in a's frame).
Pose2 compose(const Pose2& a, const Pose2& b);
// The inverse transform of p.
Pose2 inverse(const Pose2& p);

class Localisation {
 public:
  // map: the static map (non-null when cfg.enabled; must outlive this).
  Localisation(const LocalisationConfig& cfg, const OccupancyGrid* map,
               const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
               Topic<OdometryMsg>& pose);

  // Task: one tick of localisation work, then the pose out.
  void run();
  const LocalisationTelemetry& telemetry() const { return tel_; }
  // The correction map <- odom in use.
  const Pose2& map_from_odom() const { return map_from_odom_; }

 private:
  LocalisationConfig cfg_;
  const OccupancyGrid* map_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  Topic<OdometryMsg>& out_;
  Pose2 map_from_odom_;
  LocalisationTelemetry tel_;
};

}  // namespace carril::fw
