#pragma once
// The parts of a mission, for loaders that read one inside another file (a scenario's
// `mission:` section). Internal to the loaders: throws strict::LoadError.
#include <initializer_list>
#include <string>

#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::loader {

// A colour: a name (color_from_name) or [r, g, b]; `name_out` gets the name as written, or
// "[r, g, b]" with the numbers.
Rgb parse_color(const strict::Node& n, std::string* name_out = nullptr);

// Where a mission is written, which decides its keys and how messages name the robot's limit.
struct MissionSchema {
  bool file = false;  // a mission file: also behavior:, strategy_gains:, tape_preview_m
  std::string speed_limit = "robot.limits.max_speed_mps";  // the robot's speed limit, in messages
};

// Reads a `localisation:` map (initial_pose, global, initial_sigma_xy_m, initial_sigma_yaw_deg,
// recovery, and `extra_keys` the caller reads itself) into `out`.
void parse_localisation_start(const strict::Node& m, std::initializer_list<const char*> extra_keys,
                              LocalisationStartSpec& out);

// Reads the mission map `m` for `robot`: type, strategy (line_priority needs a mecanum robot),
// colours, speed (at most the robot's speed limit and what its wheels reach; the robot's cruise
// speed when omitted) and, in a file, the settings.
void parse_mission(const strict::Node& m, const RobotSpec& robot, const MissionSchema& schema,
                   MissionSpec& mission);

}  // namespace carril::loader
