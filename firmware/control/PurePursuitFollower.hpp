#pragma once
// Pure pursuit along a polyline of world waypoints for a differential-drive robot: steer on the
// arc through a point `lookahead` metres ahead on the path (curvature = 2 y_l / L^2, y_l the
// point's lateral offset in the robot frame), slowing for sharp curvature and toward the final
// point. Also the path geometry the VFF follower shares (projection, point ahead). No allocation.
#include <cstddef>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

// Where a point projects onto a polyline.
struct PathProjection {
  std::size_t segment = 0;  // index of the segment's first waypoint
  Vec2 point{0.0, 0.0};     // nearest point on the path [m]
  double distance_m = 0.0;  // from the query point to `point` [m]
};

// Nearest point on segments [from, from + window) of path[0..n) (n >= 1). Progress never goes
// back: segments before `from` are not searched.
PathProjection project_on_path(const Vec2* path, std::size_t n, const Vec2& p, std::size_t from,
                               std::size_t window);
// The point `ahead_m` metres along the path from a projection [m]; the last waypoint when the
// path ends sooner.
Vec2 point_ahead(const Vec2* path, std::size_t n, const PathProjection& from, double ahead_m);

struct PurePursuitConfig {
  double lookahead_m = 0.5;             // distance to the pursued point [m]
  double cruise_speed_mps = 0.4;        // speed on straight path [m/s]
  double min_speed_mps = 0.05;          // floor of the slow-downs (not the turn in place) [m/s]
  double max_yaw_rate_radps = 1.0;      // |wz| cap; speed is cut to keep the curvature [rad/s]
  double max_lateral_accel_mps2 = 0.5;  // v <= sqrt(a / |curvature|) [m/s^2]
  double slow_radius_m = 0.6;           // speed falls linearly inside this distance to the end [m]
  double goal_tolerance_m = 0.05;       // at the end within this distance [m]
  double rotate_in_place_rad = 1.2;     // pursued point this far off the heading: turn first [rad]
  double turn_gain = 2.0;               // turn in place: yaw rate per radian of error [1/s]

  Status validate() const;
  bool operator==(const PurePursuitConfig&) const = default;
};

class PurePursuitFollower {
 public:
  explicit PurePursuitFollower(const PurePursuitConfig& cfg = {}) : cfg_(cfg) {}
  void set_config(const PurePursuitConfig& cfg) { cfg_ = cfg; }

  // Forgets the progress (call for every new path).
  void reset();
  // Body twist [m/s, rad/s] (vy = 0) for the robot at `pose` (world) along path[0..n) (world
  // waypoints [m]). Zero twist once at the end, or for an empty path or a non-finite pose.
  Twist update(const Pose2& pose, const Vec2* path, std::size_t n);

  std::size_t progress() const { return progress_; }     // segment the robot is on
  bool at_end() const { return at_end_; }                // within goal_tolerance of the last point
  double cross_track_m() const { return cross_track_; }  // distance to the path [m]
  const Vec2& target() const { return target_; }         // last pursued point [m]

 private:
  PurePursuitConfig cfg_;
  std::size_t progress_ = 0;
  bool at_end_ = false;
  double cross_track_ = 0.0;
  Vec2 target_{0.0, 0.0};
};

}  // namespace carril::fw
