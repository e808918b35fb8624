#pragma once
// Controller files (config/controller/*.yaml), read strictly for the robot they drive: one drive
// per wheel, node ids unique, sensor sources for the sensors the robot has. Never throws.
#include <string>

#include "loader/ControllerSpec.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::loader {

// Reads the controller file at `path` for `robot` into `out` (untouched on failure). False with
// `error` = "<file>[:<line>]: <key>: <problem>" ("<file>: cannot open" for a missing file).
bool load_controller(const std::string& path, const RobotSpec& robot, ControllerSpec& out,
                     std::string& error);

// Wheels the robot's drive has: 4 for mecanum, 2 for differential.
int wheel_count(const RobotSpec& robot);

}  // namespace carril::loader
