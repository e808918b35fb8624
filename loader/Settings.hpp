#pragma once
// Component tuning by field name. A mission file's `behavior:`, `strategy_gains:` and
// `tape_preview_m`, and a tuning file's sections, each set one field of fw::FirmwareConfig; the
// table of what may be set is in Settings.cpp (and docs/configuration.md). Types are checked when
// the file is read; ranges by the component's own validate(), whose message is then traced back to
// the file, line and key that set the field.
#include <string>
#include <vector>

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

}  // namespace carril::loader
