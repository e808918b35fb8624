#pragma once
// Speed-dependent protective and warning fields, as a safety laser scanner switches them: the
// distance the robot needs to stop is worked out from its speed, its deceleration and the loop's
// worst-case reaction time (ISO 13855's S = K T + C, with K the approach speed of a person), and
// every motion request is cut to a speed whose stop fits before what the lidar sees in the
// direction of travel (ahead, behind when reversing, beside when strafing).
//
//   stop(v)         = v T + v^2 / (2 a) + C          T reaction [s], a deceleration, C margin
//   stop_time(v)    = T + v / a
//   protective(v)   = the body's band in the direction of travel, from its leading edge to
//                     stop(v), side_margin_m wider each side for moving returns: a return inside
//                     it stops the robot
//   warning(v)      = stop(v) + K stop_time(v) long, side_margin_m + K stop_time(v) wider each
//                     side: a moving return inside it cuts the speed to one whose warning field
//                     it is outside (a person starting outside the field who walks into the path
//                     cannot reach it before the robot has stopped)
//
// A static return (MovingReturns) is only what it is: in the band it cuts the speed so that its
// stop (the same, with static_margin_m for C) plus a reaction's travel fits before it, and stops
// the robot inside that stop; beside the band it does not slow the robot (a wall does not walk).
// A direction the lidar does not see (behind a front lidar) is driven at blind_speed_mps at most,
// judged on the returns remembered from before they left its view.
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/msg/ObstacleField.hpp"

namespace carril::fw {

struct SafetyFieldsConfig {
  bool enabled = true;
  // The loop's worst-case reaction (reaction_s()): a scan period (the obstacle appears just after
  // a scan), a control tick and the drive's latency. apply_sensor_rates() sets the first two
  // from the lidar's and the loop's rates.
  double scan_period_s = 0.05;    // [s]
  double tick_s = 0.01;           // [s]
  double drive_latency_s = 0.02;  // a command leaving the loop to the drive acting on it [s]
  // The deceleration of a stop: the motion limiter's limits.max_accel_mps2 (set with it) [m/s^2].
  double decel_mps2 = 1.0;
  double margin_m = 0.10;  // C: added to every stopping distance [m]
  // What a stop short of a static return keeps from it: a wall or a standing box may be come up
  // to slowly (a cleaner's lane ends at the wall), a moving return may not [m].
  double static_margin_m = 0.03;
  double side_margin_m = 0.05;      // the protective band beyond the body each side [m]
  double approach_speed_mps = 1.6;  // K: how fast something moving may approach [m/s]
  double blind_speed_mps = 0.2;     // the speed cap in a direction the lidar does not see [m/s]
  // The longest protective field the robot may need (a safety scanner's largest configurable
  // field, say); 0: no limit but the lidar's reliable range [m].
  double max_field_m = 0.0;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<SafetyFieldsConfig>> params();
  Status validate() const;
  double reaction_s() const { return scan_period_s + tick_s + drive_latency_s; }  // [s]
  double stop_m(double v) const;          // stopping distance from speed v [m]
  double stop_time_s(double v) const;     // time to a standstill from speed v [s]
  double warning_m(double v) const;       // the warning field's length ahead [m]
  double warning_side_m(double v) const;  // how far beyond the body the warning field reaches [m]
  // The stop short of a static return: v T + v^2 / (2 a) + static_margin_m [m].
  double static_stop_m(double v) const;
  // Fastest v whose static stop plus a reaction's travel (v T) fits within d [m/s].
  double static_cap_mps(double d) const;
  double warning_cap_mps(double d) const;  // fastest v whose warning field ends short of d [m/s]
  double side_cap_mps(double l) const;     // fastest v whose warning field ends short of l beside
  bool operator==(const SafetyFieldsConfig&) const = default;
};

// What the fields made of one motion request.
struct FieldVerdict {
  double scale = 1.0;        // the twist is multiplied by this [0, 1]
  bool protective = false;   // a return in the protective field: stop
  bool warning = false;      // a moving return in the warning field cut the speed
  bool static_cut = false;   // a static return in the band cut the speed
  bool blind = false;        // the direction of travel is out of the lidar's view
  double allowed_mps = 0.0;  // the speed the fields allow in this direction [m/s]
};

class SafetyFields {
 public:
  // `round_body`: the body is the disc inscribed in the footprint (its leading edge is curved).
  SafetyFields(const SafetyFieldsConfig& cfg, const Footprint& fp, bool round_body = false)
      : cfg_(cfg), fp_(fp), round_(round_body) {}

  // The request `want` (body frame) of a robot at odometry pose `pose` that moves at `v_now`
  // [m/s], against the field's returns (odometry frame). A turn in place is not judged here.
  FieldVerdict check(const ObstacleField& f, const Pose2& pose, const Twist& want,
                     double v_now) const;
  const SafetyFieldsConfig& config() const { return cfg_; }

 private:
  SafetyFieldsConfig cfg_;
  Footprint fp_;
  bool round_;
};

}  // namespace carril::fw
