#pragma once
// The robot on the height field: where its four wheels rest, the attitude that gives, and whether
// a move is physically possible for this machine (RobotSpec::terrain_limits). The robot's motion
// stays Box2D's 2D one (the horizontal projection); this only judges each move and reports the
// body's roll, pitch and height.
//
// Model: four wheels at (+-wheelbase/2, +-track/2). A wheel rests on the highest ground under its
// tyre, sampled at its centre and at +-r/2 and +-r along the heading (r = wheel radius). Per move:
//  - a wheel whose rest height rises by more than max_step_up_m in one move meets a step: blocked;
//  - a wheel whose ground along the heading gets steeper than max_slope_deg (up or down) and
//    steeper than it was: blocked (a robot already on such a slope may still leave it);
//  - a wheel whose rest height drops by more than max_step_down_m: a fall (the move happens).
// Attitude: pitch = atan((front mean - rear mean) / wheelbase), POSITIVE NOSE UP (opposite to
// REP 103's right-hand rotation about y); roll = atan((left mean - right mean) / track), positive
// left side up (REP 103); z = the mean of the four rest heights.
#include <array>

#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/world/HeightField.hpp"

namespace carril::sim {

struct Attitude {
  double roll_rad = 0.0;   // positive: left side up [rad]
  double pitch_rad = 0.0;  // positive: nose up [rad]
  double z_m = 0.0;        // body reference (centre, on the ground) height [m]
};

// What one move did. A block or a fall that starts a new contact sets new_collision (once per
// contact, like Box2D's); a fall also sets new_fall.
struct TerrainStep {
  bool blocked = false;  // the move is refused: the caller puts the robot back where it was
  bool new_collision = false;
  bool new_fall = false;
  Vec2 where;  // the wheel that blocked or fell [m], for plots
};

class TerrainContact {
 public:
  TerrainContact(const HeightField& field, const RobotSpec& robot);

  // Puts the robot at `pose` (start): wheels rest where they are, nothing is judged.
  void reset(const Pose2& pose);
  // Judges a move from the current pose to `pose`; unless blocked, the robot is there after.
  TerrainStep move_to(const Pose2& pose);

  Attitude attitude() const;
  static constexpr int kWheels = 4;  // front-left, front-right, rear-left, rear-right
  double wheel_z(int i) const { return z_[static_cast<std::size_t>(i)]; }  // [m]

 private:
  struct Rest {
    double z = 0.0;
    double slope = 0.0;  // |tan| of the ground along the heading where it rests
    Vec2 at;
  };
  Rest rest(const Pose2& p, int wheel) const;

  const HeightField& field_;
  double half_base_, half_track_, r_;
  double max_tan_slope_, max_up_, max_down_;
  double wheelbase_, track_;
  std::array<double, kWheels> z_{}, slope_{};
  Pose2 pose_;
  // One collision per contact: set at a block, cleared once the robot is 2 cm from there.
  bool blocked_latch_ = false;
  Vec2 block_xy_;
  // One fall per edge: set at a fall, cleared once the robot has moved past it (all wheels).
  bool fall_latch_ = false;
  Vec2 fall_xy_;
};

}  // namespace carril::sim
