#pragma once
// Mission files (config/missions/*.yaml), read strictly for the robot that will run them: the
// mission (type, strategy, colours, speed) and its optional tuning (behavior:, strategy_gains:,
// tape_preview_m). Never throws.
#include <string>

#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::loader {

// Reads the mission file at `path` for `robot` into `out` (untouched on failure). False with
// `error` = "<file>[:<line>]: <key>: <problem>" ("<file>: cannot open" for a missing file).
bool load_mission(const std::string& path, const RobotSpec& robot, MissionSpec& out,
                  std::string& error);

// Named colours: white, black, red, green, blue, yellow.
bool color_from_name(const std::string& name, Rgb& out);

}  // namespace carril::loader
