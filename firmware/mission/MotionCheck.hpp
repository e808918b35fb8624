#pragma once
// Every motion checked before it is commanded, whatever the mission: the footprint the motion
// sweeps before the robot could stop (its reaction time and its braking) must keep pad_m clear
// of every lethal costmap cell's centre (the static map's walls, the lidar's marks, remembered
// where the lidar cannot see now) and of every lidar return: the rule the missions' own checks
// keep (BypassPlanner::lane_clear), so it stops what they missed, not what they planned. A turn on
// the spot sweeps the corners' circle, not the front edge (a pivot at a tape corner beside a box);
// an arc or a strafe sweeps its own path. What is not clear is stopped: the runner waits, and gives
// up after its blocked timeout.
//
// The protective fields (SafetyFields) judge translation by the lidar's returns alone, in a
// straight band; this check adds the costmap, curved paths and turns in place.
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mission/BodyGuard.hpp"
#include "firmware/mission/SafetyFields.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/ObstacleField.hpp"

namespace carril::fw {

struct MotionCheckConfig {
  bool enabled = true;
  // The body is the disc inscribed in the footprint (a Roomba-class cleaner): a turn on the spot
  // sweeps nothing beyond it. From the robot file's body.shape.
  bool round_body = false;
  // The clearance the swept body keeps; what is nearer already may not come nearer (odometry and
  // lidar are good to a centimetre or two, not to the millimetre) [m].
  double pad_m = 0.03;
  double turn_margin_rad = 0.1;   // a turn is checked this much past where it could stop [rad]
  double yaw_decel_radps2 = 3.0;  // how fast a turn stops: limits.max_yaw_accel_radps2 [rad/s^2]
  // A request that is not clear is replaced by the nearest motion that is (less turn, a tighter
  // arc, the turn on the spot), not only stopped.
  bool alternatives = true;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<MotionCheckConfig>> params();
  Status validate() const;
  bool operator==(const MotionCheckConfig&) const = default;
};

struct MotionVerdict {
  bool clear = true;         // the motion may be commanded
  bool turn = false;         // it was judged as a turn on the spot
  bool crowded = false;      // too many cells near to judge: stopped
  bool alternative = false;  // the request was not clear: `twist` is the nearest that is
  double scale = 1.0;        // the translation cut to a speed whose stop fits the free travel
  double free_m = 0.0;       // the request's free travel along its path (translation) [m]
  Twist twist;               // what may be commanded (zero when not clear) [m/s, rad/s]
};

class MotionCheck {
 public:
  MotionCheck(const MotionCheckConfig& cfg, const SafetyFieldsConfig& fields, const Footprint& fp);

  // The costmap the motions are checked on, in the frame of the pose given to check() (no view
  // on it: the lidar's returns alone).
  void watch_costmap(const Topic<CostmapMsg>& c) { costmap_in_.watch(c); }
  // The request `want` of a robot at `pose` (the costmap's frame) and `odom_pose` (the obstacle
  // field's), turning at `wz_now` [rad/s] and moving at `v_now` [m/s].
  MotionVerdict check(const Twist& want, const Pose2& pose, const ObstacleField& f,
                      const Pose2& odom_pose, double v_now, double wz_now);
  std::uint64_t crowded() const { return crowded_; }  // checks refused: too many cells near

 private:
  // The translation t is clear within reach [m] at `scale` of its speed; `free`: its free travel.
  bool translation(const Twist& t, double reach, double& scale, double& free) const;
  // `out` made clear with the alternative t at `scale` of its speed.
  static MotionVerdict& take(MotionVerdict& out, const Twist& t, double scale);

  MotionCheckConfig cfg_;
  SafetyFieldsConfig fields_;
  Footprint fp_;
  CostmapInput costmap_in_;  // no view: none built
  const CostmapView* costmap() const { return costmap_in_.view(); }
  BodyGuard guard_;
  RollingGrid<std::uint8_t> no_grid_;  // never initialised: gathers nothing
  std::uint64_t crowded_ = 0;
};

}  // namespace carril::fw
