#pragma once
// Reading settings (loader/Settings.hpp) from a YAML tree. Internal to the loaders: throws
// strict::LoadError.
#include <vector>

#include "loader/Settings.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::loader {

// Reads the settings at `n`: one value when its path (`n.path()`) is a key of the table for
// `file`, else a map whose keys continue such a path (unknown keys are errors listing the allowed
// ones). Numbers must be plain and finite, integer fields take integers only.
void parse_settings(const strict::Node& n, SettingFile file, std::vector<Setting>& out);

}  // namespace carril::loader
