#pragma once
// Everything a run leaves on disk: trajectory.csv, summary.json, trajectory.png, velocities.png.
// Every file is written whole: to a temporary file in the same directory, then renamed.
#include <optional>
#include <string>
#include <vector>

#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// One row of trajectory.csv (columns t,x,y,yaw,vx,vy,wz,state,cross_track_m).
struct TrajectoryRow {
  double t = 0.0, x = 0.0, y = 0.0, yaw = 0.0;  // [s], [m], [m], [rad]
  double vx = 0.0, vy = 0.0, wz = 0.0;          // body frame [m/s], [m/s], [rad/s]
  const char* state = "";                       // firmware behaviour state name (static string)
  double cross_track_m = 0.0;
};

// Where a collision began, for the top-view plot.
struct CollisionPoint {
  double t = 0.0, x = 0.0, y = 0.0;
};

// summary.json: these keys, in this order, are the contract; more may be added, none renamed.
struct RunSummary {
  std::string scenario;
  std::string result;  // end_reached | time_limit | fault | aborted
  bool passed = false;
  double sim_time_s = 0.0, wall_time_s = 0.0, real_time_factor = 0.0;
  long ticks = 0;
  double tick_period_s = 0.0;
  long tick_overruns = 0;
  double tick_compute_p50_us = 0.0, tick_compute_p99_us = 0.0, tick_compute_max_us = 0.0;
  long heap_allocations_after_init = 0;
  int collisions = 0;
  double progress = 0.0;
  int laps = 0;
  double cross_track_rms_m = 0.0, cross_track_max_m = 0.0;
  int line_lost_events = 0, line_reacquired_events = 0, obstacles_avoided = 0;
  bool end_reached = false;
  std::optional<double> end_stop_error_m;  // null when not reached
  double path_length_m = 0.0, mean_speed_mps = 0.0, max_abs_wz_radps = 0.0;
  std::string final_state;
  // Added keys (after the contract's): why the run failed its expect block, one line per miss.
  std::vector<std::string> unmet_expectations;
  std::string fault;  // fault description when result == "fault"
};

// Writes `content` to `path` atomically (temporary file in the same directory, fsync, rename).
bool write_file_atomic(const std::string& path, const std::string& content, std::string& error);

std::string summary_to_json(const RunSummary& s);
std::string trajectory_to_csv(const std::vector<TrajectoryRow>& rows);

// Writes the four files into `dir` (created if missing). Returns false with `error` set on failure.
bool write_run_outputs(const std::string& dir, const Scenario& scenario,
                       const std::vector<TrajectoryRow>& rows,
                       const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                       std::string& error);

}  // namespace carril::sim
