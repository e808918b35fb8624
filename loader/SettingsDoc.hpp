#pragma once
// docs/configuration.md's settings tables, generated from the settings tables
// (firmware/core/Param.hpp, loader/Settings.cpp). Each table sits between two markers:
//   <!-- settings: mission -->            (or: tuning)
//   ...
//   <!-- end of settings -->
// carril_settings_doc rewrites them; SettingsTest fails when the file and the tables differ.
#include <string>

namespace carril::loader {

// `doc` with every marked table replaced by the one the tables give. False, with `error`, when a
// marker is missing, unclosed or names no file kind.
bool regenerate_settings_doc(const std::string& doc, std::string& out, std::string& error);

}  // namespace carril::loader
