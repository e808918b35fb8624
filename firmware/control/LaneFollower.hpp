#pragma once
// Follows a coverage route (straight lanes joined by arcs, a polyline with points close on the
// arcs) closely enough for the tool to reach the cells at the lane ends: the path's own
// curvature as feedforward (yaw rate = v * curvature) plus feedback on the heading and the signed
// cross-track error, instead of pure pursuit's chord (which cuts into a U-turn as soon as its
// pursued point enters it). Speed: cruise, cut where the path's curvature would need more than
// max_yaw_rate, less with a heading error, and a braking ramp toward the route's end. A pose facing
// away from the route by more than rotate_in_place_rad turns on the spot first. The route ends
// within goal_tolerance of its last point, or once the robot is past that point along the last
// segment (however wide of it). No allocation.
#include <cstddef>

#include "firmware/control/PurePursuitFollower.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct LaneFollowerConfig {
  double cruise_speed_mps = 0.3;     // on straight lanes [m/s]
  double min_speed_mps = 0.05;       // floor of the braking ramp [m/s]
  double max_yaw_rate_radps = 1.5;   // |wz| cap; the speed is cut to hold the curvature [rad/s]
  double decel_mps2 = 0.5;           // braking toward the route's end [m/s^2]
  double heading_gain = 4.0;         // yaw rate per radian of heading error [1/s]
  double cross_track_gain = 60.0;    // yaw rate per (m/s * m) of cross-track error [1/m^2]
  double curvature_window_m = 0.1;   // the feedforward curvature is measured over this [m]
  double anticipation_m = 0.0;       // ...from this far ahead of the projection [m]
  double brake_lookahead_m = 0.3;    // bends this far ahead slow the robot in time [m]
  double bend_window_m = 0.06;       // ...each measured over this (short: tight bends) [m]
  double goal_tolerance_m = 0.05;    // at the end within this distance [m]
  double rotate_in_place_rad = 0.6;  // heading error beyond this: turn on the spot [rad]
  // The robot's yaw acceleration: turning toward the path's heading (on the spot or driving)
  // brakes in time to stop on it, from the rate last asked for; 0: no such limit [rad/s^2].
  double max_yaw_accel_radps2 = 0.0;
  double period_s = 0.01;  // between update() calls (the braking allows a period's lag) [s]

  Status validate() const;
  bool operator==(const LaneFollowerConfig&) const = default;
};

class LaneFollower {
 public:
  explicit LaneFollower(const LaneFollowerConfig& cfg = {}) : cfg_(cfg) {}
  void set_config(const LaneFollowerConfig& cfg) { cfg_ = cfg; }
  // Forgets the progress (call for every new route).
  void reset();
  // Body twist [m/s, rad/s] for the robot at `pose` (world) along path[0..n) (world waypoints
  // [m]). Zero once at the end, for an empty path or a non-finite pose.
  Twist update(const Pose2& pose, const Vec2* path, std::size_t n);

  std::size_t progress() const { return progress_; }     // segment the robot is on
  bool at_end() const { return at_end_; }                // within goal_tolerance of the last point
  double cross_track_m() const { return cross_track_; }  // signed: + the path on the left [m]
  double curvature() const { return curvature_; }        // feedforward last used [1/m]

 private:
  static constexpr int kBrakeSamples = 6;  // bends looked at ahead
  Twist command(const Pose2& pose, const Vec2* path, std::size_t n);
  // The yaw rate [rad/s] that turns through heading error e [rad] at heading_gain and, with a yaw
  // acceleration limit, no faster than the robot can stop on the heading.
  double toward(double e) const;
  LaneFollowerConfig cfg_;
  std::size_t progress_ = 0;
  bool at_end_ = false;
  double wz_last_ = 0.0;  // the yaw rate last asked for [rad/s]
  double cross_track_ = 0.0, curvature_ = 0.0;
};

// The path's heading at projection `at` [rad], and its curvature between arc lengths s0 and s1
// ahead of it: the circle through the path's points at s0, (s0 + s1) / 2 and s1 [1/m]; + turns
// left, 0 where the path ends sooner.
double path_heading(const Vec2* path, std::size_t n, const PathProjection& at);
double path_curvature(const Vec2* path, std::size_t n, const PathProjection& at, double s0,
                      double s1);

}  // namespace carril::fw
