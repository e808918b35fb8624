#include "loader/Settings.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <limits>

#include "firmware/app/FirmwareConfig.hpp"
#include "loader/SettingsYaml.hpp"

namespace carril::loader {

namespace {

using fw::FirmwareConfig;

// One tunable field: its key in the file, the name FirmwareConfig::validate() gives it in its
// messages, and where it lives (exactly one of number / integer is set).
struct Field {
  SettingFile file;
  const char* key;
  const char* field;
  double* (*number)(FirmwareConfig&);
  int* (*integer)(FirmwareConfig&);
};

// Capture-free lambdas: each entry reads as "key -> validate()'s name -> member".
#define CARRIL_NUMBER(file, key, field, member)                                         \
  Field {                                                                               \
    SettingFile::file, key, field, [](FirmwareConfig& c) { return &c.member; }, nullptr \
  }
#define CARRIL_INTEGER(file, key, field, member)                                        \
  Field {                                                                               \
    SettingFile::file, key, field, nullptr, [](FirmwareConfig& c) { return &c.member; } \
  }

// Fields derived from the robot (geometry, mounts, rates, limits) and the mission (colours,
// strategy, speed) are not here: they have one source, the robot or mission file.
const Field kFields[] = {
    // Mission file: the follow_line state machine (BehaviorConfig).
    CARRIL_NUMBER(Mission, "behavior.init_timeout_s", "behavior.init_timeout_s",
                  follow_line.behavior.init_timeout_s),
    CARRIL_NUMBER(Mission, "behavior.search_yaw_rate_radps", "behavior.search_yaw_rate_radps",
                  follow_line.behavior.search_yaw_rate_radps),
    CARRIL_NUMBER(Mission, "behavior.start_max_turn_rad", "behavior.start_max_turn_rad",
                  follow_line.behavior.start_max_turn_rad),
    CARRIL_INTEGER(Mission, "behavior.lost_frames", "behavior.lost_frames",
                   follow_line.behavior.lost_frames),
    CARRIL_NUMBER(Mission, "behavior.memory_trust_m", "behavior.memory_trust_m",
                  follow_line.behavior.memory_trust_m),
    CARRIL_NUMBER(Mission, "behavior.memory_trust_s", "behavior.memory_trust_s",
                  follow_line.behavior.memory_trust_s),
    CARRIL_NUMBER(Mission, "behavior.pid_lost_grace_s", "behavior.pid_lost_grace_s",
                  follow_line.behavior.pid_lost_grace_s),
    CARRIL_NUMBER(Mission, "behavior.end_approach_m", "behavior.end_approach_m",
                  follow_line.behavior.end_approach_m),
    CARRIL_NUMBER(Mission, "behavior.end_speed_mps", "behavior.end_speed_mps",
                  follow_line.behavior.end_speed_mps),
    CARRIL_NUMBER(Mission, "behavior.end_gain", "behavior.end_gain", follow_line.behavior.end_gain),
    CARRIL_NUMBER(Mission, "behavior.end_tolerance_m", "behavior.end_tolerance_m",
                  follow_line.behavior.end_tolerance_m),
    CARRIL_NUMBER(Mission, "behavior.align_tolerance_rad", "behavior.align_tolerance_rad",
                  follow_line.behavior.align_tolerance_rad),
    CARRIL_NUMBER(Mission, "behavior.start_on_tape_lateral_m", "behavior.start_on_tape_lateral_m",
                  follow_line.behavior.start_on_tape_lateral_m),
    CARRIL_NUMBER(Mission, "behavior.start_on_tape_angle_rad", "behavior.start_on_tape_angle_rad",
                  follow_line.behavior.start_on_tape_angle_rad),
    CARRIL_NUMBER(Mission, "behavior.reacquire_on_path_m", "behavior.reacquire_on_path_m",
                  follow_line.behavior.reacquire_on_path_m),
    CARRIL_NUMBER(Mission, "behavior.end_reach_m", "behavior.end_reach_m",
                  follow_line.behavior.end_reach_m),
    CARRIL_NUMBER(Mission, "behavior.end_reveal_m", "behavior.end_reveal_m",
                  follow_line.behavior.end_reveal_m),
    // Mission file: obstacle avoidance (AvoidConfig).
    CARRIL_NUMBER(Mission, "behavior.avoid.corridor_margin_m", "behavior.avoid.corridor_margin_m",
                  follow_line.behavior.avoid.corridor_margin_m),
    CARRIL_NUMBER(Mission, "behavior.avoid.clearance_m", "behavior.avoid.clearance_m",
                  follow_line.behavior.avoid.clearance_m),
    CARRIL_NUMBER(Mission, "behavior.avoid.speed_mps", "behavior.avoid.speed_mps",
                  follow_line.behavior.avoid.speed_mps),
    CARRIL_NUMBER(Mission, "behavior.avoid.emergency_m", "behavior.avoid.emergency_m",
                  follow_line.behavior.avoid.emergency_m),
    CARRIL_NUMBER(Mission, "behavior.avoid.max_lateral_m", "behavior.avoid.max_lateral_m",
                  follow_line.behavior.avoid.max_lateral_m),
    CARRIL_NUMBER(Mission, "behavior.avoid.blocked_timeout_s", "behavior.avoid.blocked_timeout_s",
                  follow_line.behavior.avoid.blocked_timeout_s),
    CARRIL_NUMBER(Mission, "behavior.avoid.lookahead_m", "behavior.avoid.lookahead_m",
                  follow_line.behavior.avoid.lookahead_m),
    // Mission file: the strategies' gains (StrategyConfig; the strategy and its cruise speed are
    // the mission's `strategy` and `speed_mps`).
    CARRIL_NUMBER(Mission, "strategy_gains.marks_lookahead_m", "strategy.marks_lookahead_m",
                  follow_line.strategy.marks_lookahead_m),
    CARRIL_NUMBER(Mission, "strategy_gains.lp_k_lateral", "strategy.lp_k_lateral",
                  follow_line.strategy.lp_k_lateral),
    CARRIL_NUMBER(Mission, "strategy_gains.lp_k_angle", "strategy.lp_k_angle",
                  follow_line.strategy.lp_k_angle),
    CARRIL_NUMBER(Mission, "strategy_gains.lp_k_lateral_w", "strategy.lp_k_lateral_w",
                  follow_line.strategy.lp_k_lateral_w),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_lookahead_m", "strategy.pid_lookahead_m",
                  follow_line.strategy.pid_lookahead_m),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_error_scale_m", "strategy.pid_error_scale_m",
                  follow_line.strategy.pid_error_scale_m),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_curve_threshold", "strategy.pid_curve_threshold",
                  follow_line.strategy.pid_curve_threshold),
    // validate() names a PID gain set as a whole ("strategy.pid_straight: ...").
    CARRIL_NUMBER(Mission, "strategy_gains.pid_straight.kp", "strategy.pid_straight",
                  follow_line.strategy.pid_straight.kp),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_straight.ki", "strategy.pid_straight",
                  follow_line.strategy.pid_straight.ki),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_straight.kd", "strategy.pid_straight",
                  follow_line.strategy.pid_straight.kd),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_straight.speed_mps", "strategy.pid_straight",
                  follow_line.strategy.pid_straight.speed_mps),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_curve.kp", "strategy.pid_curve",
                  follow_line.strategy.pid_curve.kp),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_curve.ki", "strategy.pid_curve",
                  follow_line.strategy.pid_curve.ki),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_curve.kd", "strategy.pid_curve",
                  follow_line.strategy.pid_curve.kd),
    CARRIL_NUMBER(Mission, "strategy_gains.pid_curve.speed_mps", "strategy.pid_curve",
                  follow_line.strategy.pid_curve.speed_mps),
    CARRIL_NUMBER(Mission, "strategy_gains.heading_gain", "strategy.heading_gain",
                  follow_line.strategy.heading_gain),
    CARRIL_NUMBER(Mission, "strategy_gains.corner_turn_rad", "strategy.corner_turn_rad",
                  follow_line.strategy.corner_turn_rad),
    CARRIL_NUMBER(Mission, "strategy_gains.corner_slow_m", "strategy.corner_slow_m",
                  follow_line.strategy.corner_slow_m),
    CARRIL_NUMBER(Mission, "strategy_gains.corner_min_speed_mps", "strategy.corner_min_speed_mps",
                  follow_line.strategy.corner_min_speed_mps),
    CARRIL_NUMBER(Mission, "strategy_gains.pivot_heading_rad", "strategy.pivot_heading_rad",
                  follow_line.strategy.pivot_heading_rad),
    CARRIL_NUMBER(Mission, "strategy_gains.max_yaw_rate_radps", "strategy.max_yaw_rate_radps",
                  follow_line.strategy.max_yaw_rate_radps),
    CARRIL_NUMBER(Mission, "tape_preview_m", "follow_line.tape_preview_m",
                  follow_line.tape_preview_m),

    // Tuning file: the mission runner's obstacle stop.
    CARRIL_NUMBER(Tuning, "runner.obstacle.stop_m", "runner.obstacle.stop_m",
                  runner.obstacle.stop_m),
    CARRIL_NUMBER(Tuning, "runner.obstacle.corridor_margin_m", "runner.obstacle.corridor_margin_m",
                  runner.obstacle.corridor_margin_m),
    // Tuning file: the protective and warning fields (the reaction's scan period and tick, and
    // the deceleration, come from the robot's rates and limits).
    CARRIL_NUMBER(Tuning, "runner.fields.drive_latency_s", "runner.fields.drive_latency_s",
                  runner.fields.drive_latency_s),
    CARRIL_NUMBER(Tuning, "runner.fields.margin_m", "runner.fields.margin_m",
                  runner.fields.margin_m),
    CARRIL_NUMBER(Tuning, "runner.fields.static_margin_m", "runner.fields.static_margin_m",
                  runner.fields.static_margin_m),
    CARRIL_NUMBER(Tuning, "runner.fields.side_margin_m", "runner.fields.side_margin_m",
                  runner.fields.side_margin_m),
    CARRIL_NUMBER(Tuning, "runner.fields.approach_speed_mps", "runner.fields.approach_speed_mps",
                  runner.fields.approach_speed_mps),
    CARRIL_NUMBER(Tuning, "runner.fields.blind_speed_mps", "runner.fields.blind_speed_mps",
                  runner.fields.blind_speed_mps),
    CARRIL_NUMBER(Tuning, "runner.fields.max_field_m", "runner.fields.max_field_m",
                  runner.fields.max_field_m),
    // Tuning file: the swept-footprint check of every motion.
    CARRIL_NUMBER(Tuning, "runner.check.pad_m", "runner.check.pad_m", runner.check.pad_m),
    CARRIL_NUMBER(Tuning, "runner.check.turn_margin_rad", "runner.check.turn_margin_rad",
                  runner.check.turn_margin_rad),
    // Tuning file: how long a stopped motion or a mission without progress is waited for.
    CARRIL_NUMBER(Tuning, "runner.blocked_timeout_s", "runner.blocked_timeout_s",
                  runner.blocked_timeout_s),
    CARRIL_NUMBER(Tuning, "runner.stall_timeout_s", "runner.stall_timeout_s",
                  runner.stall_timeout_s),
    CARRIL_NUMBER(Tuning, "runner.stall_progress_m", "runner.stall_progress_m",
                  runner.stall_progress_m),
    // Tuning file: which lidar returns are something moving.
    CARRIL_NUMBER(Tuning, "lidar.moving.history_s", "lidar.moving.history_s",
                  lidar.moving.history_s),
    CARRIL_NUMBER(Tuning, "lidar.moving.margin_m", "lidar.moving.margin_m", lidar.moving.margin_m),
    CARRIL_NUMBER(Tuning, "lidar.moving.margin_per_m", "lidar.moving.margin_per_m",
                  lidar.moving.margin_per_m),
    // The tape detector (its colour windows come from the mission's colours).
    CARRIL_INTEGER(Tuning, "detector.decimation", "detector.decimation",
                   camera.detector.decimation),
    CARRIL_NUMBER(Tuning, "detector.tape_width_m", "detector.tape_width_m",
                  camera.detector.tape_width_m),
    CARRIL_NUMBER(Tuning, "detector.min_piece_m", "detector.min_piece_m",
                  camera.detector.min_piece_m),
    CARRIL_NUMBER(Tuning, "detector.min_area_px", "detector.min_area_px",
                  camera.detector.min_area_px),
    CARRIL_NUMBER(Tuning, "detector.min_end_area_px", "detector.min_end_area_px",
                  camera.detector.min_end_area_px),
    // Sensor health rules; windows derived from the rates unless set here.
    CARRIL_INTEGER(Tuning, "health.scan.window_scans", "health.scan.window_scans",
                   lidar.health.window_scans),
    CARRIL_NUMBER(Tuning, "health.scan.min_valid_fraction", "health.scan.min_valid_fraction",
                  lidar.health.min_valid_fraction),
    CARRIL_INTEGER(Tuning, "health.frame.sample_step_px", "health.frame.sample_step_px",
                   camera.health.sample_step_px),
    CARRIL_INTEGER(Tuning, "health.frame.blank_tolerance", "health.frame.blank_tolerance",
                   camera.health.blank_tolerance),
    CARRIL_INTEGER(Tuning, "health.frame.blank_frames", "health.frame.blank_frames",
                   camera.health.blank_frames),
    CARRIL_NUMBER(Tuning, "health.frame.frozen_motion_m", "health.frame.frozen_motion_m",
                  camera.health.frozen_motion_m),
    CARRIL_NUMBER(Tuning, "health.frame.frozen_turn_rad", "health.frame.frozen_turn_rad",
                  camera.health.frozen_turn_rad),
    CARRIL_NUMBER(Tuning, "health.imu.max_tilt_rad", "health.imu.max_tilt_rad",
                  watch.imu.max_tilt_rad),
    CARRIL_NUMBER(Tuning, "health.imu.max_yaw_rate_radps", "health.imu.max_yaw_rate_radps",
                  watch.imu.max_yaw_rate_radps),
    CARRIL_INTEGER(Tuning, "health.imu.out_of_range_samples", "health.imu.out_of_range_samples",
                   watch.imu.out_of_range_samples),
    CARRIL_NUMBER(Tuning, "health.imu.frozen_s", "health.imu.frozen_s", watch.imu.frozen_s),
    CARRIL_NUMBER(Tuning, "health.imu.frozen_min_turn_change_radps",
                  "health.imu.frozen_min_turn_change_radps",
                  watch.imu.frozen_min_turn_change_radps),
    // Device timeouts; derived from the rates unless set here.
    CARRIL_NUMBER(Tuning, "watch.camera_timeout_s", "watch.camera_timeout_s",
                  watch.camera_timeout_s),
    CARRIL_NUMBER(Tuning, "watch.scanner_timeout_s", "watch.scanner_timeout_s",
                  watch.scanner_timeout_s),
    CARRIL_NUMBER(Tuning, "watch.imu_timeout_s", "watch.imu_timeout_s", watch.imu_timeout_s),
    // The task table's budgets (Firmware::declare_tasks, both targets).
    CARRIL_NUMBER(Tuning, "tasks.health_us", "tasks.health_us", tasks.health_us),
    CARRIL_NUMBER(Tuning, "tasks.odometry_us", "tasks.odometry_us", tasks.odometry_us),
    CARRIL_NUMBER(Tuning, "tasks.localisation_us", "tasks.localisation_us", tasks.localisation_us),
    CARRIL_NUMBER(Tuning, "tasks.perception_us", "tasks.perception_us", tasks.perception_us),
    CARRIL_NUMBER(Tuning, "tasks.obstacles_us", "tasks.obstacles_us", tasks.obstacles_us),
    CARRIL_NUMBER(Tuning, "tasks.mapping_us", "tasks.mapping_us", tasks.mapping_us),
    CARRIL_NUMBER(Tuning, "tasks.mission_us", "tasks.mission_us", tasks.mission_us),
    CARRIL_NUMBER(Tuning, "tasks.motion_us", "tasks.motion_us", tasks.motion_us),
    CARRIL_NUMBER(Tuning, "tasks.telemetry_us", "tasks.telemetry_us", tasks.telemetry_us),
    // The one motion limit the robot description does not carry.
    CARRIL_NUMBER(Tuning, "limits.max_yaw_accel_radps2", "limits.max_yaw_accel_radps2",
                  limits.max_yaw_accel_radps2),
};

#undef CARRIL_NUMBER
#undef CARRIL_INTEGER

const Field* find(SettingFile file, const std::string& key) {
  for (const Field& f : kFields) {
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
    if (f->number != nullptr) {
      *f->number(c) = s.value;
    } else {
      *f->integer(c) = static_cast<int>(s.value);
    }
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
    const std::string_view name = f->field;
    if (name == field ||
        (name.size() > field.size() && name.starts_with(field) && name[field.size()] == '.')) {
      out = where(s) + ": " + firmware_message.substr(colon + 2);
      return true;
    }
  }
  return false;
}

std::vector<std::string> setting_keys(SettingFile file) {
  std::vector<std::string> keys;
  for (const Field& f : kFields) {
    if (f.file == file) keys.emplace_back(f.key);
  }
  return keys;
}

void parse_settings(const strict::Node& n, SettingFile file, std::vector<Setting>& out) {
  const std::string& path = n.path();
  if (const Field* f = find(file, path)) {
    double v = 0.0;
    if (f->number != nullptr) {
      v = n.number();
    } else {
      // Any integer is read; its range is the component's (validate()), once it fits an int.
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
  for (const Field& f : kFields) {
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
