#pragma once
// Component tuning files (config/tuning/*.yaml): optional settings of the firmware's components
// by field name (runner.obstacle, detector, health, watch, limits), read strictly. A key left out
// keeps the component's default, or the value derived from the robot's rates. Never throws.
#include <string>
#include <vector>

#include "loader/Settings.hpp"

namespace carril::loader {

struct Tuning {
  std::vector<Setting> settings;
  std::string source_path;  // the file it was read from
};

// Reads the tuning file at `path` into `out` (untouched on failure). False with `error` =
// "<file>[:<line>]: <key>: <problem>" ("<file>: cannot open" for a missing file). Ranges are
// checked when the configuration is built (build_firmware_config), by the components.
bool load_tuning(const std::string& path, Tuning& out, std::string& error);

}  // namespace carril::loader
