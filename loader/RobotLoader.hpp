#pragma once
// Robot descriptions (config/robots/<name>.yaml), read strictly: every key of the format is
// required unless docs/configuration.md says otherwise, unknown keys, wrong types and values out
// of range are errors. Never throws.
#include <string>

#include "loader/RobotSpec.hpp"

namespace carril::loader {

// Reads the robot description at `path` into `out` (untouched on failure). False with `error` =
// "<file>[:<line>]: <key>: <problem>" ("<file>: cannot open" for a missing file).
bool load_robot_preset(const std::string& path, RobotSpec& out, std::string& error);

}  // namespace carril::loader
