#pragma once
// Motion primitives every mission shares: turn on the spot to a heading, drive to a point, drive
// through a list of waypoints holding a heading, and creep onto a goal point and stop on it. Pure
// functions of the pose; the robot's drive type decides how a point is reached (a holonomic
// robot translates, a differential one turns first).
#include <cstddef>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct PathTrackerConfig {
  double turn_gain = 2.0;            // yaw rate per radian of heading error [1/s]
  double max_turn_rate_radps = 0.6;  // turning on the spot [rad/s]
  double reached_m = 0.04;           // a waypoint is reached this close [m]

  Status validate() const;
  bool operator==(const PathTrackerConfig&) const = default;
};

class PathTracker {
 public:
  PathTracker(const PathTrackerConfig& cfg, bool holonomic) : cfg_(cfg), holonomic_(holonomic) {}

  // Turn on the spot toward heading `target` [rad].
  Twist turn_to(const Pose2& odom, double target) const;
  // Toward waypoint `wp` (odometry frame) at up to `speed_mps`, holding `hold_heading` (holonomic).
  // `reached` is set within reached_m.
  Twist drive_to(const Pose2& odom, const Vec2& wp, double hold_heading, double speed_mps,
                 bool& reached) const;
  // Along waypoints[index..n): drives to waypoints[index] and advances `index` when it is
  // reached. Returns zero twist and sets `done` once the last one is reached.
  Twist follow(const Pose2& odom, const Vec2* waypoints, std::size_t n, std::size_t& index,
               double hold_heading, double speed_mps, bool& done) const;
  // Creeps onto `goal` at min(max_speed, gain * distance) and reports `arrived` within
  // `tolerance_m` (a differential robot also once the goal is beside or behind it, within 5 cm).
  Twist approach(const Pose2& odom, const Vec2& goal, double max_speed_mps, double gain,
                 double tolerance_m, bool& arrived) const;
  bool holonomic() const { return holonomic_; }

 private:
  PathTrackerConfig cfg_;
  bool holonomic_;
};

}  // namespace carril::fw
