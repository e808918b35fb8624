#pragma once
// A mission as a mission file (config/missions/*.yaml) or a scenario's `mission:` section writes
// it: what to follow, in which colours, how, how fast, and the component tuning that goes with it.
#include <cstdint>
#include <string>
#include <vector>

#include "loader/Settings.hpp"

namespace carril::loader {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

// A goal pose or waypoint as a mission section writes it.
struct GoalSpec {
  double x_m = 0.0, y_m = 0.0;  // [m]
  double yaw_deg = 0.0;         // [deg]
};

// Where a mission on a known map starts (a mission file's or a scenario's `localisation:`): what
// the robot is told of its pose, and whether Monte Carlo localisation may re-seed itself.
struct LocalisationStartSpec {
  bool has_initial_pose = false;       // false: the robot's start (a scenario) or the map's origin
  GoalSpec initial_pose;               // map frame [m, m, deg]
  bool global = false;                 // no pose given: particles over all the free space
  double initial_sigma_xy_m = 0.3;     // spread of the particles round initial_pose [m]
  double initial_sigma_yaw_rad = 0.2;  // [rad] (written in degrees)
  bool recovery = false;  // augmented MCL's random injection (needed to recover from a kidnap)
  double max_unlocalised_s = 60.0;  // held unlocalised this long: fault not_localised; 0 never [s]
};

struct MissionSpec {
  std::string type = "follow_line";  // follow_line | goto | waypoints
  std::string strategy = "pid";      // line_priority | marks | pid
  Rgb line_color{255, 255, 255};
  std::string line_color_name = "white";  // name as written, or "[r, g, b]"
  Rgb end_color{255, 255, 0};
  std::string end_color_name = "yellow";
  double speed_mps =
      0.5;  // cruise speed; the robot's cruise_speed_mps when the file omits it [m/s]
  // goto: the goal pose (a mission file: odometry frame, i.e. relative to where the robot
  // starts; a scenario: world frame, converted by the simulator), the local follower, and
  // whether the planner may cross cells never observed.
  double goal_x_m = 0.0, goal_y_m = 0.0;  // [m]
  double goal_yaw_deg = 0.0;              // [deg]
  std::string follower = "pure_pursuit";  // pure_pursuit | vff
  bool allow_unknown = true;
  // goto through several goals (`goals:`, the taxi): in order; empty with a single `goal:`.
  std::vector<GoalSpec> goals;
  // waypoints (a course followed with VFF): the targets (yaw unused), laps, how close counts.
  std::vector<GoalSpec> targets;
  int laps = 1;
  double reach_radius_m = 0.25;  // [m]
  // coverage (cleaning): systematic (boustrophedon on the map) or vacuum (the reactive baseline),
  // the tool's width, the area (a polygon in the map frame; empty: the map's free space), and a
  // time limit (the vacuum's run time).
  std::string coverage_mode = "systematic";
  double tool_width_m = 0.0;       // 0: the robot's width [m]
  double wall_clearance_m = 0.0;   // the lanes keep this beyond the robot's inscribed radius [m]
  double transit_speed_mps = 0.0;  // between cells; 0: speed_mps [m/s]
  double lane_overlap = 0.1;       // neighbouring lanes overlap by this fraction of the tool [-]
  std::vector<GoalSpec> area;
  double max_time_s = 1800.0;  // [s]
  // A mission file's known map (`map:`, resolved against the file's folder; "" without one)
  // and where the robot starts on it. With a map, goals and targets are in the map frame.
  std::string map_path;
  LocalisationStartSpec localisation;
  std::vector<Setting> settings;  // a mission file's behavior:, strategy_gains:, tape_preview_m
  std::string source_path;        // the mission file ("" for a scenario's section)
};

}  // namespace carril::loader
