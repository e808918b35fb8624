#pragma once
// Getting round an obstacle that stands on the tape, without a global planner: in the tape's own
// frame (x along the tape, y to its left), the obstacle's outline from the lidar decides the
// freer side; waypoints keep `clearance_m` between body and obstacle while passing and lead back
// onto the tape beyond it. The plan grows as the lidar sees more of the obstacle's far side.
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/msg/ObstacleField.hpp"

namespace carril::fw {

struct AvoidConfig {
  double corridor_margin_m = 0.10;  // corridor = robot width + this each side [m]
  // (The obstacle that starts an avoidance is the mission runner's: ObstacleStopConfig.)
  double clearance_m = 0.30;       // body-to-obstacle clearance while passing [m]
  double speed_mps = 0.30;         // bypass speed [m/s]
  double emergency_m = 0.05;       // any point this close to the body stops the robot [m]
  double max_lateral_m = 2.5;      // never detour further than this from the tape [m]
  double blocked_timeout_s = 3.0;  // stopped this long by something in the way: give up [s]
  // Only an obstacle starting within this of the bumper, along the tape, is planned round: after
  // turning onto the tape out of a curve, what stopped the robot may stand beside the tape, and
  // a wall far down the tape is not in the way yet [m].
  double lookahead_m = 2.0;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<AvoidConfig>> params();
  Status validate() const;
  bool operator==(const AvoidConfig&) const = default;
};

struct BypassPlan {
  bool ok = false;
  bool blocked = false;        // an obstacle is there but neither side has room
  int side = 0;                // +1 pass on the tape's left, -1 on its right
  Vec2 origin = Vec2::Zero();  // tape frame origin, odometry frame
  double heading = 0.0;        // tape direction, odometry frame [rad]
  double x_near = 0.0, x_far = 0.0, y_min = 0.0, y_max = 0.0;  // obstacle extent, tape frame
  double lateral = 0.0;             // offset of the passing lane, tape frame [m]
  StaticVector<Vec2, 4> waypoints;  // odometry frame, in order
};

class BypassPlanner {
 public:
  // `holonomic`: the robot keeps the tape's heading while it passes (mecanum); otherwise it
  // faces along each leg and turns on the spot at its ends.
  BypassPlanner(const AvoidConfig& cfg, const Footprint& fp, bool holonomic)
      : cfg_(cfg), fp_(fp), holonomic_(holonomic) {}

  // Plans round the obstacle nearest ahead of a robot at `odom` on a tape through `tape_point`
  // with direction `tape_heading` (both odometry frame).
  // With a costmap, the lane the outline chose is checked on it (lane_clear); when it is blocked
  // it moves out in steps of kLaneStepM up to max_lateral_m, then the other side is tried the
  // same way, and the plan is blocked when no lane is clear. `excluded_side` (+1 left, -1
  // right, 0 none) is a side already found blocked: only the other is considered.
  BypassPlan plan(const ObstacleField& f, const Pose2& odom, const Vec2& tape_point,
                  double tape_heading, const RollingGrid<std::uint8_t>* costmap = nullptr,
                  int excluded_side = 0) const;
  // Whether the robot, driven from `from` through p's waypoints [first, n), keeps its whole body
  // at least emergency_m off every lethal cell of `costmap` (a cell's centre at least
  // emergency_m + one cell off): the area its rectangle sweeps along each leg (holding the
  // tape's heading, or facing along the leg), and for a differential robot the circle it sweeps
  // turning at each leg's start and at the end. Cells outside the window count as clear; cells
  // under the body where it stands now are not judged (the emergency stop guards those).
  bool lane_clear(const BypassPlan& p, const Pose2& from, std::size_t first,
                  const RollingGrid<std::uint8_t>& costmap) const;
  static constexpr double kLaneStepM = 0.1;  // how far a blocked lane moves out per try [m]
  // One bypass passes at most this many obstacles standing where the robot would rejoin the tape
  // (each found extends it), over at most kMaxBypassM along the tape [m].
  static constexpr int kMaxMerges = 8;
  static constexpr double kMaxBypassM = 8.0;
  // Extends `p` if a newer scan shows the obstacle reaching further along the tape, or another
  // one (in the scan or the costmap) where the robot would rejoin the tape.
  void refine(const ObstacleField& f, BypassPlan& p,
              const RollingGrid<std::uint8_t>* costmap = nullptr) const;

 private:
  void set_waypoints(BypassPlan& p, double x_robot) const;
  // Extends p's extent over every return and lethal cell standing in the band the robot would
  // rejoin the tape on beyond p's far end, until that stretch is clear (the bypass then passes
  // them all); false when the obstacles run on further than kMaxBypassM or kMaxMerges.
  bool cover_rejoin(BypassPlan& p, const ObstacleField& f,
                    const RollingGrid<std::uint8_t>* costmap) const;
  // The body's rectangle at c, facing u, grown by a margin: half length and half width [m].
  struct Rect {
    Vec2 c = Vec2::Zero(), u = Vec2::UnitX();
    double hl = 0.0, hw = 0.0;
  };
  Rect grown(const Vec2& c, double yaw, double margin) const;
  // No lethal cell's centre inside the area swept sliding from r0 to r1, outside `here`.
  static bool sweep_clear(const Rect& r0, const Rect& r1, const Rect& here,
                          const RollingGrid<std::uint8_t>& costmap);
  // Nothing lethal within `radius` [m] of `c` (the circle a body turning on the spot sweeps).
  static bool disc_clear(const Vec2& c, double radius, const RollingGrid<std::uint8_t>& costmap);
  AvoidConfig cfg_;
  Footprint fp_;
  bool holonomic_;
};

}  // namespace carril::fw
