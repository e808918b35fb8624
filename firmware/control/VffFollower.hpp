#pragma once
// Virtual force field local follower for a differential-drive robot: attraction toward a carrot
// `carrot_lookahead` metres ahead on the path plus repulsion from the costmap cells near the
// robot (cost >= a threshold), each pushing away with gain * cost/254 * exp(-distance / scale).
// The resultant's direction is the heading to hold: turn on the spot when far off it, otherwise
// drive at a speed scaled by the cosine of the error. Reads the costmap, never allocates.
#include <cstddef>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct VffConfig {
  double carrot_lookahead_m = 0.6;  // carrot distance ahead of the robot's projection [m]
  double attraction_gain = 1.0;     // magnitude of the pull toward the carrot [-]
  double repulsion_gain = 0.5;      // per cell at distance 0 and cost 254 [-]
  double repulsion_radius_m = 0.8;  // cells farther than this do not push [m]
  double repulsion_scale_m = 0.25;  // exp(-d / scale) fall-off [m]
  // The summed push is capped at this fraction of the pull: it deflects the robot round what the
  // planner's path passes, never cancels the pull (a wall face of many cells would otherwise
  // outweigh the carrot and hold the robot in a local minimum) [-].
  double max_repulsion_ratio = 0.8;
  int cost_threshold = 253;         // cells with cost >= this push (1..254)
  bool unknown_repels = false;      // unknown (255) cells push too, as lethal
  double cruise_speed_mps = 0.4;    // [m/s]
  double min_speed_mps = 0.05;      // floor of the slow-down toward the end [m/s]
  double slow_radius_m = 0.6;       // speed falls linearly inside this distance to the end [m]
  double max_yaw_rate_radps = 1.0;  // [rad/s]
  double turn_gain = 2.0;           // yaw rate per radian of heading error [1/s]
  double turn_in_place_rad = 0.8;   // heading error above which the robot only turns [rad]
  double goal_tolerance_m = 0.05;   // at the end within this distance [m]

  Status validate() const;
  bool operator==(const VffConfig&) const = default;
};

class VffFollower {
 public:
  explicit VffFollower(const VffConfig& cfg = {}) : cfg_(cfg) {}
  void set_config(const VffConfig& cfg) { cfg_ = cfg; }

  // Forgets the progress (call for every new path).
  void reset();
  // Body twist [m/s, rad/s] (vy = 0) for the robot at `pose` along path[0..n) (world waypoints
  // [m]) with `costmap` (world-aligned window). Zero twist at the end, for an empty path, a
  // non-finite pose, or forces that cancel.
  Twist update(const Pose2& pose, const Vec2* path, std::size_t n,
               const RollingGrid<std::uint8_t>& costmap);

  std::size_t progress() const { return progress_; }  // segment the robot is on
  bool at_end() const { return at_end_; }
  const Vec2& carrot() const { return carrot_; }          // [m]
  const Vec2& attraction() const { return attraction_; }  // last force, world frame
  const Vec2& repulsion() const { return repulsion_; }    // last force, world frame

 private:
  Vec2 repulsion_at(const Vec2& p, const RollingGrid<std::uint8_t>& costmap) const;

  VffConfig cfg_;
  std::size_t progress_ = 0;
  bool at_end_ = false;
  Vec2 carrot_{0.0, 0.0};
  Vec2 attraction_{0.0, 0.0};
  Vec2 repulsion_{0.0, 0.0};
};

}  // namespace carril::fw
