#pragma once
// Shared helpers for the loader tests: the source tree's config files, files written to a
// temporary directory, and a field-by-field comparison of two firmware configurations.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "firmware/app/FirmwareConfig.hpp"
#include "loader/MissionLoader.hpp"
#include "loader/RobotLoader.hpp"

namespace carril::loader::test {

inline std::string source_path(const std::string& relative) {
  return std::string(CARRIL_SOURCE_DIR) + "/" + relative;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Writes `text` to <temp dir>/carril_loader_test_<pid>/<name> and returns its path. One folder
// per process: CTest runs each test in its own process, several at once (-j), and two tests that
// write the same file name must not read each other's.
inline std::string write_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("carril_loader_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

// `text` with the first occurrence of `from` (which must exist) replaced by `to`.
inline std::string edit(const std::string& text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "text does not contain: " << from;
  if (pos == std::string::npos) return text;
  std::string out = text;
  out.replace(pos, from.size(), to);
  return out;
}

inline RobotSpec robot(const std::string& name) {
  RobotSpec r;
  std::string error;
  EXPECT_TRUE(load_robot_preset(source_path("config/robots/" + name + ".yaml"), r, error)) << error;
  return r;
}

// Every field of `a` equals the same field of `b`, exactly (bit for bit for doubles but NaN).
inline void expect_same(const fw::FirmwareConfig& a, const fw::FirmwareConfig& b) {
#define CARRIL_SAME(field) EXPECT_EQ(a.field, b.field) << #field
  CARRIL_SAME(rate_hz);
  CARRIL_SAME(drive.type);
  CARRIL_SAME(drive.wheel_radius_m);
  CARRIL_SAME(drive.wheelbase_m);
  CARRIL_SAME(drive.track_m);
  CARRIL_SAME(footprint_length_m);
  CARRIL_SAME(footprint_width_m);
  CARRIL_SAME(limits.max_speed_mps);
  CARRIL_SAME(limits.max_yaw_rate_radps);
  CARRIL_SAME(limits.max_accel_mps2);
  CARRIL_SAME(limits.max_yaw_accel_radps2);
  CARRIL_SAME(limits.max_wheel_speed_radps);
  CARRIL_SAME(camera.camera.x_m);
  CARRIL_SAME(camera.camera.y_m);
  CARRIL_SAME(camera.camera.z_m);
  CARRIL_SAME(camera.camera.tilt_rad);
  CARRIL_SAME(camera.camera.hfov_rad);
  CARRIL_SAME(camera.camera.width);
  CARRIL_SAME(camera.camera.height);
  CARRIL_SAME(camera.rate_hz);
  for (auto t : {&fw::LineDetectorConfig::line, &fw::LineDetectorConfig::end}) {
    const fw::ColorThreshold& ta = a.camera.detector.*t;
    const fw::ColorThreshold& tb = b.camera.detector.*t;
    EXPECT_EQ(ta.h_lo, tb.h_lo);
    EXPECT_EQ(ta.h_hi, tb.h_hi);
    EXPECT_EQ(ta.s_lo, tb.s_lo);
    EXPECT_EQ(ta.s_hi, tb.s_hi);
    EXPECT_EQ(ta.v_lo, tb.v_lo);
    EXPECT_EQ(ta.v_hi, tb.v_hi);
  }
  CARRIL_SAME(camera.detector.decimation);
  CARRIL_SAME(camera.detector.tape_width_m);
  CARRIL_SAME(camera.detector.min_piece_m);
  CARRIL_SAME(camera.detector.min_area_px);
  CARRIL_SAME(camera.detector.min_end_area_px);
  CARRIL_SAME(camera.health.sample_step_px);
  CARRIL_SAME(camera.health.blank_tolerance);
  CARRIL_SAME(camera.health.blank_frames);
  CARRIL_SAME(camera.health.frozen_motion_m);
  CARRIL_SAME(camera.health.frozen_turn_rad);
  CARRIL_SAME(lidar.present);
  CARRIL_SAME(lidar.x_m);
  CARRIL_SAME(lidar.y_m);
  CARRIL_SAME(lidar.yaw_rad);
  CARRIL_SAME(lidar.rate_hz);
  CARRIL_SAME(lidar.health.window_scans);
  CARRIL_SAME(lidar.health.min_valid_fraction);
  CARRIL_SAME(watch.camera_timeout_s);
  CARRIL_SAME(watch.scanner_timeout_s);
  CARRIL_SAME(watch.imu_present);
  CARRIL_SAME(watch.imu.max_tilt_rad);
  CARRIL_SAME(watch.imu.max_yaw_rate_radps);
  CARRIL_SAME(watch.imu.out_of_range_samples);
  CARRIL_SAME(watch.imu.frozen_s);
  CARRIL_SAME(watch.imu.frozen_min_turn_change_radps);
  CARRIL_SAME(runner.obstacle.stop_m);
  CARRIL_SAME(runner.obstacle.corridor_margin_m);
  CARRIL_SAME(runner.fields.drive_latency_s);
  CARRIL_SAME(runner.fields.margin_m);
  CARRIL_SAME(runner.fields.static_margin_m);
  CARRIL_SAME(runner.check.pad_m);
  CARRIL_SAME(runner.check.round_body);
  CARRIL_SAME(runner.check.turn_margin_rad);
  CARRIL_SAME(runner.fields.side_margin_m);
  CARRIL_SAME(runner.fields.approach_speed_mps);
  CARRIL_SAME(runner.fields.blind_speed_mps);
  CARRIL_SAME(runner.fields.max_field_m);
  CARRIL_SAME(runner.fields.scan_period_s);
  CARRIL_SAME(runner.fields.tick_s);
  CARRIL_SAME(runner.fields.decel_mps2);
  CARRIL_SAME(runner.blocked_timeout_s);
  CARRIL_SAME(runner.stall_timeout_s);
  CARRIL_SAME(runner.stall_progress_m);
  CARRIL_SAME(lidar.moving.history_s);
  CARRIL_SAME(lidar.moving.margin_m);
  CARRIL_SAME(lidar.moving.margin_per_m);
  CARRIL_SAME(lidar.reliable_range_m);
  CARRIL_SAME(follow_line.strategy.strategy);
  CARRIL_SAME(follow_line.strategy.speed_mps);
  CARRIL_SAME(follow_line.strategy.marks_lookahead_m);
  CARRIL_SAME(follow_line.strategy.lp_k_lateral);
  CARRIL_SAME(follow_line.strategy.lp_k_angle);
  CARRIL_SAME(follow_line.strategy.lp_k_lateral_w);
  CARRIL_SAME(follow_line.strategy.pid_lookahead_m);
  CARRIL_SAME(follow_line.strategy.pid_error_scale_m);
  CARRIL_SAME(follow_line.strategy.pid_curve_threshold);
  CARRIL_SAME(follow_line.strategy.pid_straight.kp);
  CARRIL_SAME(follow_line.strategy.pid_straight.ki);
  CARRIL_SAME(follow_line.strategy.pid_straight.kd);
  CARRIL_SAME(follow_line.strategy.pid_straight.speed_mps);
  CARRIL_SAME(follow_line.strategy.pid_curve.kp);
  CARRIL_SAME(follow_line.strategy.pid_curve.ki);
  CARRIL_SAME(follow_line.strategy.pid_curve.kd);
  CARRIL_SAME(follow_line.strategy.pid_curve.speed_mps);
  CARRIL_SAME(follow_line.strategy.heading_gain);
  CARRIL_SAME(follow_line.strategy.corner_turn_rad);
  CARRIL_SAME(follow_line.strategy.corner_slow_m);
  CARRIL_SAME(follow_line.strategy.corner_min_speed_mps);
  CARRIL_SAME(follow_line.strategy.pivot_heading_rad);
  CARRIL_SAME(follow_line.strategy.max_yaw_rate_radps);
  CARRIL_SAME(follow_line.behavior.init_timeout_s);
  CARRIL_SAME(follow_line.behavior.search_yaw_rate_radps);
  CARRIL_SAME(follow_line.behavior.start_max_turn_rad);
  CARRIL_SAME(follow_line.behavior.lost_frames);
  CARRIL_SAME(follow_line.behavior.memory_trust_m);
  CARRIL_SAME(follow_line.behavior.memory_trust_s);
  CARRIL_SAME(follow_line.behavior.pid_lost_grace_s);
  CARRIL_SAME(follow_line.behavior.end_approach_m);
  CARRIL_SAME(follow_line.behavior.end_speed_mps);
  CARRIL_SAME(follow_line.behavior.end_gain);
  CARRIL_SAME(follow_line.behavior.end_tolerance_m);
  CARRIL_SAME(follow_line.behavior.align_tolerance_rad);
  CARRIL_SAME(follow_line.behavior.start_on_tape_lateral_m);
  CARRIL_SAME(follow_line.behavior.start_on_tape_angle_rad);
  CARRIL_SAME(follow_line.behavior.reacquire_on_path_m);
  CARRIL_SAME(follow_line.behavior.end_reach_m);
  CARRIL_SAME(follow_line.behavior.end_reveal_m);
  CARRIL_SAME(follow_line.behavior.avoid.corridor_margin_m);
  CARRIL_SAME(follow_line.behavior.avoid.clearance_m);
  CARRIL_SAME(follow_line.behavior.avoid.speed_mps);
  CARRIL_SAME(follow_line.behavior.avoid.emergency_m);
  CARRIL_SAME(follow_line.behavior.avoid.max_lateral_m);
  CARRIL_SAME(follow_line.behavior.avoid.blocked_timeout_s);
  CARRIL_SAME(follow_line.behavior.avoid.lookahead_m);
  CARRIL_SAME(follow_line.tape_preview_m);
#undef CARRIL_SAME
}

}  // namespace carril::loader::test
