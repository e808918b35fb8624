#include "loader/Settings.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/core/Param.hpp"
#include "loader/SettingsYaml.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::loader {

namespace {

using fw::FirmwareConfig;

// One tunable field, flattened out of its struct's table (firmware/core/Param.hpp): its key in
// the file, the name FirmwareConfig::validate() gives it, and how to reach it.
struct Field {
  SettingFile file;
  std::string key;
  std::string field;
  fw::ParamInfo info;
  bool integer = false;
  std::function<void(FirmwareConfig&, double)> set;
  std::function<double(FirmwareConfig&)> get;
};

// Every tunable row of Cfg's table, under `key_prefix` in the file and `field_prefix` in
// validate()'s messages; `of` reaches the struct inside the configuration.
template <class Cfg>
void add(std::vector<Field>& out, SettingFile file, const std::string& key_prefix,
         const std::string& field_prefix, Cfg& (*of)(FirmwareConfig&)) {
  for (const fw::Param<Cfg>& p : Cfg::params()) {
    if (!p.info.tunable) continue;
    out.push_back({file, key_prefix + p.info.name, field_prefix + p.info.name, p.info,
                   p.is_integer(), [p, of](FirmwareConfig& c, double v) { p.set(of(c), v); },
                   [p, of](FirmwareConfig& c) { return p.get(of(c)); }});
  }
}

// The sections of the two files, in the order the docs list them. Fields derived from the robot
// (geometry, mounts, rates, limits) and the mission (colours, strategy, speed) are marked not
// tunable in their tables: they have one source, the robot or mission file.
std::vector<Field> make_fields() {
  std::vector<Field> v;
// Struct `Type` at `member` of the configuration, read under `key` in the file; `field` is the
// name validate() gives it (the scope of its Checks).
#define CARRIL_SECTION(file, key, field, Type, member) \
  add<fw::Type>(v, SettingFile::file, key, field,      \
                [](FirmwareConfig& c) -> fw::Type& { return c.member; })
  // Mission file: the follow_line state machine, its obstacle avoidance, the followers' gains.
  CARRIL_SECTION(Mission, "behavior.", "behavior.", BehaviorConfig, follow_line.behavior);
  CARRIL_SECTION(Mission, "behavior.avoid.", "behavior.avoid.", AvoidConfig,
                 follow_line.behavior.avoid);
  CARRIL_SECTION(Mission, "strategy_gains.", "strategy.", StrategyConfig, follow_line.strategy);
  CARRIL_SECTION(Mission, "strategy_gains.pid_straight.", "strategy.pid_straight.", PidGains,
                 follow_line.strategy.pid_straight);
  CARRIL_SECTION(Mission, "strategy_gains.pid_curve.", "strategy.pid_curve.", PidGains,
                 follow_line.strategy.pid_curve);
  CARRIL_SECTION(Mission, "", "follow_line.", FollowLineConfig, follow_line);
  // Tuning file.
  CARRIL_SECTION(Tuning, "runner.obstacle.", "runner.obstacle.", ObstacleStopConfig,
                 runner.obstacle);
  CARRIL_SECTION(Tuning, "runner.fields.", "runner.fields.", SafetyFieldsConfig, runner.fields);
  CARRIL_SECTION(Tuning, "runner.check.", "runner.check.", MotionCheckConfig, runner.check);
  CARRIL_SECTION(Tuning, "runner.", "runner.", MissionRunnerConfig, runner);
  CARRIL_SECTION(Tuning, "lidar.moving.", "lidar.moving.", MovingReturnsConfig, lidar.moving);
  CARRIL_SECTION(Tuning, "detector.", "detector.", LineDetectorConfig, camera.detector);
  CARRIL_SECTION(Tuning, "health.scan.", "health.scan.", ScanHealthConfig, lidar.health);
  CARRIL_SECTION(Tuning, "health.frame.", "health.frame.", FrameHealthConfig, camera.health);
  CARRIL_SECTION(Tuning, "health.imu.", "health.imu.", ImuHealthConfig, watch.imu);
  CARRIL_SECTION(Tuning, "watch.", "watch.", SensorWatchConfig, watch);
  CARRIL_SECTION(Tuning, "tasks.", "tasks.", TaskBudgets, tasks);
  CARRIL_SECTION(Tuning, "limits.", "limits.", MotionLimits, limits);
#undef CARRIL_SECTION
  return v;
}

const std::vector<Field>& fields() {
  static const std::vector<Field> kFields = make_fields();
  return kFields;
}

const Field* find(SettingFile file, const std::string& key) {
  for (const Field& f : fields()) {
    if (f.file == file && key == f.key) return &f;
  }
  return nullptr;
}

// A key from either file (a Setting does not record which kind of file it came from; the two
// tables share no key).
const Field* find(const std::string& key) {
  const Field* f = find(SettingFile::Mission, key);
  return f != nullptr ? f : find(SettingFile::Tuning, key);
}

std::string where(const Setting& s) {
  return s.file + (s.line > 0 ? ":" + std::to_string(s.line) : std::string()) + ": " + s.key;
}

}  // namespace

bool apply_settings(const std::vector<Setting>& settings, FirmwareConfig& c, std::string& error) {
  for (const Setting& s : settings) {
    const Field* f = find(s.key);
    if (f == nullptr) {
      error = where(s) + ": not a tunable field";
      return false;
    }
    f->set(c, s.value);
  }
  return true;
}

bool explain_with_settings(const std::vector<Setting>& settings,
                           const std::string& firmware_message, std::string& out) {
  const auto colon = firmware_message.find(": ");
  if (colon == std::string::npos) return false;
  const std::string field = firmware_message.substr(0, colon);
  for (const Setting& s : settings) {
    const Field* f = find(s.key);
    if (f == nullptr) continue;
    const std::string& name = f->field;
    if (name == field ||
        (name.size() > field.size() && name.starts_with(field) && name[field.size()] == '.')) {
      out = where(s) + ": " + firmware_message.substr(colon + 2);
      return true;
    }
  }
  return false;
}

std::vector<SettingInfo> settings_info(SettingFile file) {
  FirmwareConfig defaults;
  std::vector<SettingInfo> out;
  for (const Field& f : fields()) {
    if (f.file == file) out.push_back({f.key, f.field, f.info, f.integer, f.get(defaults)});
  }
  return out;
}

std::vector<std::string> setting_keys(SettingFile file) {
  std::vector<std::string> keys;
  for (const Field& f : fields()) {
    if (f.file == file) keys.push_back(f.key);
  }
  return keys;
}

namespace {

// A number as the docs write it: 6 significant digits, exponents short (1e6, not 1e+06).
std::string doc_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  std::string s = buf;
  for (const char* from : {"e+0", "e+", "e-0"}) {
    if (const auto at = s.find(from); at != std::string::npos) {
      s.replace(at, std::char_traits<char>::length(from), from[1] == '-' ? "e-" : "e");
      break;
    }
  }
  return s;
}

}  // namespace

std::string settings_markdown(SettingFile file) {
  FirmwareConfig defaults;
  std::string md = "| key | unit | default | range | meaning |\n| --- | --- | --- | --- | --- |\n";
  for (const Field& f : fields()) {
    if (f.file != file) continue;
    const std::string unit = std::string(f.info.unit) + (f.integer ? " (integer)" : "");
    const std::string dflt = f.info.derived != nullptr ? std::string("derived: ") + f.info.derived
                                                       : doc_number(f.get(defaults));
    md += "| `" + f.key + "` | " + unit + " | " + dflt + " | [" + doc_number(f.info.min) + ", " +
          doc_number(f.info.max) + "] | " + f.info.description + " |\n";
  }
  return md;
}

void parse_settings(const strict::Node& n, SettingFile file, std::vector<Setting>& out) {
  const std::string& path = n.path();
  if (const Field* f = find(file, path)) {
    double v = 0.0;
    if (!f->integer) {
      v = n.number();
    } else {
      // Any integer is read; its range is the table's (checked by validate()), once it fits.
      const std::int64_t i = n.integer(std::numeric_limits<std::int64_t>::min(),
                                       std::numeric_limits<std::int64_t>::max());
      if (i < INT_MIN || i > INT_MAX) {
        n.expected(
            "an integer in [" + std::to_string(INT_MIN) + ", " + std::to_string(INT_MAX) + "]",
            n.raw());
      }
      v = static_cast<double>(i);
    }
    out.push_back({path, v, n.file(), n.line()});
    return;
  }
  // A section: its keys are the next parts of the table's keys under `path`.
  const std::string prefix = path.empty() ? "" : path + ".";
  std::vector<std::string> allowed;
  for (const Field& f : fields()) {
    const std::string_view key = f.key;
    if (f.file != file || !key.starts_with(prefix)) continue;
    const std::string_view rest = key.substr(prefix.size());
    std::string next(rest.substr(0, rest.find('.')));
    if (std::find(allowed.begin(), allowed.end(), next) == allowed.end()) {
      allowed.push_back(std::move(next));
    }
  }
  n.expect_map(allowed);
  for (const std::string& key : allowed) {
    if (auto child = n.get(key)) parse_settings(*child, file, out);
  }
}

}  // namespace carril::loader
