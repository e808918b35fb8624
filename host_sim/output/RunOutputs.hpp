#pragma once
// Everything a run leaves on disk: trajectory.csv, summary.json, trajectory.png, velocities.png.
// The four replace the previous run's as one set: they are written into a staging directory
// beside the output directory, synced, and the staging directory is swapped in with one rename.
#include <functional>
#include <optional>
#include <string>
#include <utility>
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
  int collisions = 0;      // contacts while the robot was moving (movers included)
  int mover_contacts = 0;  // contacts a mover made with the robot standing still
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
  // The mission, whatever it is: its name, how it ended (starting, active, finishing, done,
  // failed) and every count it keeps (the line counts above are three of follow_line's).
  std::string mission;
  std::string mission_status;
  std::vector<std::pair<std::string, long>> mission_counters;
  // Throttled task-overrun events of the firmware (this host's compute time against each
  // task's budget: at most one per task and second).
  long task_overrun_events = 0;
  // goto (null for other missions): whether the robot stopped on the goal within 0.1 m and
  // 10 deg, its errors from the true pose, and the plans remade because the costmap blocked one.
  std::optional<bool> goal_reached;
  std::optional<double> goal_error_m, goal_yaw_error_deg;  // [m], [deg]
  long replans = 0;
  int cells_checked = 0;  // expect.cells entries checked against the costmap
  // Drops beyond the robot's terrain_limits.max_step_down_m driven off (each also a collision).
  int falls = 0;
  // Localisation on a map (null without one): errors of the firmware's pose from the true pose
  // after it converged (within 0.2 m and 5 deg for good), when it converged, and per kidnap how
  // long until it was back within those bounds (null: never).
  std::optional<double> localisation_rmse_m, localisation_max_error_m, yaw_rmse_deg;
  std::optional<double> time_to_converge_s;
  std::optional<double> relocalised_after_kidnap_s;                // the first kidnap's
  std::vector<std::optional<double>> relocalised_after_kidnaps_s;  // every kidnap's
  // The firmware's localisation counters (empty without a map): lost, lost_by_fit,
  // relocalisations, spreads, wrong_convergences (LocalisationTelemetry).
  std::vector<std::pair<std::string, long>> localisation_counters;
  // What the protective fields and the motion checks did (MissionRunnerTelemetry): ticks a
  // motion was stopped or cut by each, ticks driven where the lidar does not see, lidar returns
  // marked moving; and the longest a motion was kept stopped [s].
  std::vector<std::pair<std::string, long>> safety_counters;
  double blocked_max_s = 0.0;
  // coverage (null for other missions): the swept fraction of the area a robot of this size can
  // sweep from its start, the fraction of swept cells swept more than once, that area, the lower
  // bound on the time (area / (tool width x speed)) and the run's time over it.
  std::optional<double> coverage, coverage_overlap, coverage_area_m2, coverage_lower_bound_s,
      coverage_time_ratio;
  // Each firmware task's compute time on this host (shared, noisy: figures, not goals).
  struct TaskTime {
    std::string name;
    long runs = 0, overruns = 0;
    double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
  };
  std::vector<TaskTime> tasks;
};

// Writes `content` to `path` atomically (temporary file in the same directory, fsync, rename).
bool write_file_atomic(const std::string& path, const std::string& content, std::string& error);

std::string summary_to_json(const RunSummary& s);
std::string trajectory_to_csv(const std::vector<TrajectoryRow>& rows);

// Checks, before a run, that `dir` can take its outputs: `dir` is missing or a directory holding
// nothing but a previous run's four files (and stale temporaries of a write that was cut short),
// since the whole directory is replaced; its parent directories are created; a staging directory
// with a probe file can be created beside it (then removed). Returns false with `error` (naming
// the path and the OS's reason) otherwise.
bool prepare_output_dir(const std::string& dir, std::string& error);

// Writes the four files (with `plots` false the two data files, no PNGs) and swaps them in for
// `dir` as one set: into a fresh staging directory
// `.<name>.tmp.<pid>` in `dir`'s parent, each synced, then an atomic exchange with `dir`
// (renameat2 RENAME_EXCHANGE; a plain rename when `dir` does not exist; where the filesystem
// cannot exchange, `dir` is renamed aside to `.<name>.old.<pid>` first and restored if the second
// rename fails), then the previous set is removed. The same refusal as prepare_output_dir applies.
// On failure returns false with `error` set, the previous set is left as it was and the staging
// directory is removed; a crash at any point leaves either the old or the new set whole under
// `dir` or beside it, never a mix.
// Writes further files of the set into the staging directory `dir` (a run with a costmap:
// costmap.png, costmap.pgm, costmap.yaml, traversability.png, obstacles.png, elevation.cmap);
// false with `error` when one cannot be written.
using ExtraOutputs = std::function<bool(const std::string& dir, std::string& error)>;

bool write_run_outputs(const std::string& dir, const Scenario& scenario,
                       const std::vector<TrajectoryRow>& rows,
                       const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                       std::string& error, const ExtraOutputs& extra = {}, bool plots = true);

// Test hook: makes the next write_run_outputs calls fail at `step` until reset with "". Steps: a
// file name ("trajectory.csv", "trajectory.png", "velocities.png", "summary.json": writing that
// file into the staging directory fails), "swap" (the final rename fails), "no_exchange" (not a
// failure: the filesystem is taken not to support RENAME_EXCHANGE, so the fallback runs).
void set_output_fault_for_test(const std::string& step);

}  // namespace carril::sim
