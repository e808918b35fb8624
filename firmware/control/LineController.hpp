#pragma once
// The three line-following strategies of the source thesis, done with metric errors measured at
// the robot (from the TapeMap) instead of pixel offsets:
//  - marks: pursuit of a look-ahead point on the remembered tape (odometry frame) at constant
//    speed, angular rate from the bearing to the point (both drive types);
//  - line_priority: constant forward speed, lateral velocity from the tape's lateral offset,
//    angular rate from the tape angle (mecanum only: it strafes);
//  - pid: PID on the lateral error with two gain sets and speeds (straights, curves) chosen by
//    the error's size, v = v_max / (|w| + 1) in curves; when the tape is lost the error
//    saturates to +-1 with the sign of the last error.
// Every strategy slows before sharp corners and turns on the spot when the tape turns more than
// the robot can follow on the move (the thesis lost the tape on corners over 70 deg).
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/perception/TapeMap.hpp"

namespace carril::fw {

enum class Strategy : std::uint8_t { Marks, LinePriority, Pid };

inline const char* strategy_name(Strategy s) {
  switch (s) {
    case Strategy::Marks:
      return "marks";
    case Strategy::LinePriority:
      return "line_priority";
    case Strategy::Pid:
      return "pid";
  }
  return "?";
}

struct PidGains {
  double kp = 0.0, ki = 0.0, kd = 0.0;  // on the normalised error [rad/s per unit]
  double speed_mps = 0.5;               // [m/s]
  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<PidGains>> params();
  bool operator==(const PidGains&) const = default;
};

struct StrategyConfig {
  Strategy strategy = Strategy::Marks;
  double speed_mps = 0.5;  // cruise [m/s]
  // marks
  double marks_lookahead_m = 0.30;
  // line_priority
  double lp_k_lateral = 2.5;    // lateral velocity per metre of offset [1/s]
  double lp_k_angle = 3.0;      // yaw rate per radian of tape angle [1/s]
  double lp_k_lateral_w = 0.0;  // yaw rate per metre of offset subtracted (thesis's lateral term)
  // pid
  double pid_lookahead_m = 0.30;      // the error is the tape's lateral offset this far ahead
  double pid_error_scale_m = 0.25;    // offset that counts as error 1 (edge of the thesis's image)
  double pid_curve_threshold = 0.25;  // |error| above this uses the curve gains
  PidGains pid_straight{2.2, 0.0, 0.08, 0.5};
  PidGains pid_curve{3.0, 0.0, 0.10, 0.4};
  // all strategies
  double heading_gain = 2.0;           // yaw rate per radian of heading error (marks, pid) [1/s]
  double corner_turn_rad = 0.6;        // a turn sharper than this within the preview is a corner
  double corner_slow_m = 0.8;          // start slowing this far before a corner [m]
  double corner_min_speed_mps = 0.12;  // speed at the corner [m/s]
  double pivot_heading_rad = 0.5;      // heading error above this: turn on the spot
  double max_yaw_rate_radps = 1.2;     // [rad/s]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<StrategyConfig>> params();
  Status validate() const;
  bool operator==(const StrategyConfig&) const = default;
};

class LineController {
 public:
  LineController(const StrategyConfig& cfg, bool holonomic);

  // Command while the tape is tracked.
  Twist follow(const TrackState& t, double dt_s);
  // Command while the tape is not tracked (pid: saturated error; others: zero).
  Twist lost(double dt_s);
  void reset();
  const StrategyConfig& config() const { return cfg_; }

 private:
  double corner_speed(const TrackState& t) const;
  Twist pivot_or(const TrackState& t, const Twist& moving) const;
  Twist marks(const TrackState& t);
  Twist line_priority(const TrackState& t);
  Twist pid(const TrackState& t, double dt_s);

  StrategyConfig cfg_;
  bool holonomic_;
  double integral_ = 0.0;
  double last_error_ = 0.0;
  bool have_last_ = false;
};

}  // namespace carril::fw
