#pragma once
// Component: where the robot is in the map frame. Without a map it passes odometry through (the
// map frame is then the odometry frame). On a known map it runs Monte Carlo localisation
// (firmware/estimation/MonteCarloLocalizer) on the 2D scans, spread over ticks with a particle
// budget per tick, and publishes every tick the odometry pose carried into the map frame by the
// newest correction (map <- odom, as AMCL's transform): smooth between scans, corrected at each
// completed update. The missions and the costmap read this pose.
#include <cstdint>

#include <memory>
#include "firmware/core/Frames.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"

#include "firmware/estimation/MonteCarloLocalizer.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

struct LocalisationConfig {
  bool enabled = false;  // a static map is given: localise on it
  Pose2 initial_pose;    // the robot's start as the operator gives it, map frame [m, m, rad]
  bool global = false;   // no start given: particles spread over the whole free space
  double initial_sigma_xy_m = 0.5;      // spread round initial_pose [m]
  double initial_sigma_yaw_rad = 0.35;  // [rad]
  MclConfig mcl;
  int particles_per_tick = 500;  // the filter's work per tick (~0.1 ms) [particles]
  // The 2D lidar's mount in the robot frame [m, m, rad].
  Pose2 lidar_mount;
  // Localised while the estimate's standard deviation stays within these (and lost beyond twice
  // them): the missions drive only then [m], [rad].
  double localised_sigma_xy_m = 0.15;
  double localised_sigma_yaw_rad = 0.1;

  Status validate() const;
};

struct LocalisationTelemetry {
  std::uint64_t updates = 0;   // completed measurement updates
  Pose2 pose;                  // the published pose, map frame [m, m, rad]
  double sigma_xy_m = 0.0;     // the estimate's position spread (largest axis) [m]
  double sigma_yaw_rad = 0.0;  // its yaw spread [rad]
  int particles = 0;           // particles in the filter
  bool localised = true;
  std::uint32_t lost = 0;  // times it went from localised to not
  MclTelemetry mcl;
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
  const LocalisationTelemetry& telemetry() const;
  // The correction map <- odom in use.
  const Pose2& map_from_odom() const { return map_from_odom_; }
  // The filter (nullptr without a map).
  const MonteCarloLocalizer* filter() const { return mcl_.get(); }

 private:
  LocalisationConfig cfg_;
  const OccupancyGrid* map_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  Topic<OdometryMsg>& out_;
  Pose2 map_from_odom_;
  std::unique_ptr<MonteCarloLocalizer> mcl_;
  std::uint32_t last_scan_seq_ = 0;
  std::uint64_t seen_updates_ = 0;
  bool localised_ = false;
  void take_estimate();
  mutable LocalisationTelemetry tel_;
};

}  // namespace carril::fw
