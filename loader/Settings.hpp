#pragma once
// Component tuning by field name. A mission file's `behavior:`, `strategy_gains:` and
// `tape_preview_m`, and a tuning file's sections, each set one field of fw::FirmwareConfig. What
// may be set, its type, unit, range and meaning are the components' settings tables
// (firmware/core/Param.hpp); Settings.cpp only says under which key of which file each struct's
// table is read. Types are checked when the file is read; ranges by the component's validate()
// (from the same table), whose message is then traced back to the file, line and key.
#include <string>
#include <vector>

#include "firmware/core/Param.hpp"

// Declared only: a mission (MissionSpec) holds settings, and code that reads missions without
// building a configuration (the simulator's scoring) need not see the firmware.
namespace carril::fw {
struct FirmwareConfig;
}

namespace carril::loader {

// The kind of file a setting may be written in.
enum class SettingFile { Mission, Tuning };

// One value set from a file, with where it was written (for messages).
struct Setting {
  std::string key;     // key path in the file: "behavior.avoid.clearance_m"
  double value = 0.0;  // as written (integers exactly)
  std::string file;    // the file it was read from
  int line = 0;        // 1-based line; 0 when unknown
};

// Sets each setting's field in `c`, in order. False, with `error` naming the file and key, for a
// key that is not in the table (only settings made in code can have one).
bool apply_settings(const std::vector<Setting>& settings, fw::FirmwareConfig& c,
                    std::string& error);

// For a FirmwareConfig::validate() message ("<scope>.<field>: <problem>"), the setting that set
// that field: `out` = "<file>:<line>: <key>: <problem>". False when no setting set it.
bool explain_with_settings(const std::vector<Setting>& settings,
                           const std::string& firmware_message, std::string& out);

// Every key a file of that kind accepts, in table order.
std::vector<std::string> setting_keys(SettingFile file);

// One key of a file, as its struct's table declares it.
struct SettingInfo {
  std::string key;       // in the file: "strategy_gains.pid_curve.kp"
  std::string field;     // in validate()'s messages: "strategy.pid_curve.kp"
  fw::ParamInfo info;    // unit, range, meaning
  bool integer = false;  // an int member: the file must give an integer
  double default_value;  // a default-constructed FirmwareConfig's (see info.derived)
};
std::vector<SettingInfo> settings_info(SettingFile file);

// The markdown table of a file's keys (key, unit, default, range, meaning), as
// docs/configuration.md shows it; defaults are a default-constructed FirmwareConfig's.
std::string settings_markdown(SettingFile file);

}  // namespace carril::loader
