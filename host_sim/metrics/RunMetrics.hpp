#pragma once
// Scores a run tick by tick against the scenario: cross-track, progress along the reference path
// in order, laps, distance travelled, speeds, collisions, end-mark stop error.
#include <optional>
#include <vector>

#include "host_sim/metrics/ReferencePath.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// What the simulator knows about one tick after the firmware ran and the physics advanced.
struct TickSample {
  double t_s = 0.0;
  Pose2 pose;                         // true pose in the world
  double vx_mps = 0.0, vy_mps = 0.0;  // true body-frame velocity [m/s]
  double wz_radps = 0.0;              // true yaw rate [rad/s]
  bool following = false;             // the firmware is in a line-following state
  bool in_end_state = false;          // the firmware is in its END state
};

class RunMetrics {
 public:
  explicit RunMetrics(const Scenario& scenario);

  // Adds one tick; returns its cross-track distance to the reference path [m]
  // (0 when the scenario has no reference path).
  double add(const TickSample& s);
  void add_collision() { ++collisions_; }
  // A drop beyond the robot's limit driven off (SimWorld counts it as a collision too).
  void add_fall() { ++falls_; }

  // True once the robot has stopped (speed < 1 cm/s, |wz| < 0.02 rad/s) in its END state with
  // its centre within 0.25 m of an end mark.
  bool end_reached() const { return end_error_m_.has_value(); }
  std::optional<double> end_stop_error_m() const { return end_error_m_; }

  int collisions() const { return collisions_; }
  int falls() const { return falls_; }
  double progress() const;  // [0, 1]
  int laps() const;
  double cross_track_rms_m() const;  // over following ticks; 0 if none
  double cross_track_max_m() const;  // over following ticks; 0 if none
  double path_length_m() const { return path_length_m_; }
  double mean_speed_mps() const;  // path length / elapsed time
  double max_abs_wz_radps() const { return max_abs_wz_; }
  const ReferencePath& path() const { return path_; }

 private:
  double remaining_m() const;  // in-order path distance left to cover [m]

  const Scenario& scenario_;
  ReferencePath path_;
  std::vector<Vec2> end_marks_;  // centres of marks of the mission's end colour
  bool started_ = false;
  double s_m_ = 0.0;         // current arc position on the path (wrapped if closed) [m]
  double advanced_m_ = 0.0;  // total in-order advance along the path [m]
  double s0_m_ = 0.0;        // arc position of the first sample's projection [m]
  double off_path_m_ = 0.0;  // driven since the robot was last on the tape [m]
  double first_t_s_ = 0.0, last_t_s_ = 0.0;
  Vec2 last_xy_;
  double path_length_m_ = 0.0;
  double sum_sq_ct_ = 0.0, max_ct_ = 0.0;
  long following_ticks_ = 0;
  double max_abs_wz_ = 0.0;
  int collisions_ = 0;
  int falls_ = 0;
  std::optional<double> end_error_m_;
};

}  // namespace carril::sim
