// Tuning files: every key maps to a component's field; unknown keys, wrong types and (when the
// configuration is built) out-of-range values name the file, line and key.
#include "loader/TuningLoader.hpp"

#include <gtest/gtest.h>

#include "loader/FirmwareConfigBuilder.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::robot;
using test::source_path;
using test::write_file;

struct Loaded {
  bool ok = false;
  Tuning tuning;
  std::string error;
  std::string path;
};

Loaded load(const std::string& text) {
  Loaded l;
  l.path = write_file("tuning.yaml", text);
  l.ok = load_tuning(l.path, l.tuning, l.error);
  return l;
}

// The error of building campero's configuration with `text` as the tuning file.
std::string build_error(const std::string& text, std::string* path = nullptr) {
  const Loaded l = load(text);
  EXPECT_TRUE(l.ok) << l.error;
  if (path != nullptr) *path = l.path;
  MissionSpec m;
  m.strategy = "marks";
  const BuildResult b = build_firmware_config(robot("campero"), m, &l.tuning);
  EXPECT_FALSE(b.ok) << "built";
  return b.error;
}

TEST(TuningLoader, ShippedFileLoads) {
  Tuning t;
  std::string error;
  const std::string path = source_path("config/tuning/default.yaml");
  ASSERT_TRUE(load_tuning(path, t, error)) << error;
  EXPECT_EQ(t.source_path, path);
  EXPECT_EQ(t.settings.size(), 42U);  // 33, and the nine task budgets
}

TEST(TuningLoader, UnknownKeysListTheAllowedOnes) {
  const Loaded top = load("runer: {obstacle: {stop_m: 0.5}}\n");
  EXPECT_EQ(top.error, top.path +
                           ":1: runer: unknown key (allowed: runner, lidar, detector, health, "
                           "watch, tasks, limits)");
  const Loaded nested = load("detector:\n  decimate: 2\n");
  EXPECT_EQ(nested.error,
            nested.path +
                ":2: detector.decimate: unknown key (allowed: "
                "decimation, tape_width_m, min_piece_m, min_area_px, min_end_area_px)");
  // The robot's own limits are its description's, not tuning.
  const Loaded limit = load("limits: {max_speed_mps: 0.5}\n");
  EXPECT_EQ(limit.error, limit.path +
                             ":1: limits.max_speed_mps: unknown key (allowed: "
                             "max_yaw_accel_radps2)");
  const Loaded dup = load("watch: {camera_timeout_s: 0.3, camera_timeout_s: 0.4}\n");
  EXPECT_NE(dup.error.find("watch.camera_timeout_s: duplicate key"), std::string::npos)
      << dup.error;
}

TEST(TuningLoader, WrongTypesNameFileLineAndKey) {
  const Loaded frac = load("detector: {decimation: 2.5}\n");
  EXPECT_EQ(frac.error, frac.path + ":1: detector.decimation: expected an integer, got 2.5");
  const Loaded word = load("runner:\n  obstacle:\n    stop_m: far\n");
  EXPECT_EQ(word.error, word.path + ":3: runner.obstacle.stop_m: expected a number, got \"far\"");
  const Loaded section = load("health: {scan: 5}\n");
  EXPECT_EQ(section.error, section.path + ":1: health.scan: expected a map, got \"5\"");
  const Loaded nan = load("health: {imu: {frozen_s: .nan}}\n");
  EXPECT_EQ(nan.error, nan.path + ":1: health.imu.frozen_s: expected a finite number, got .nan");
  const Loaded huge = load("health: {frame: {blank_frames: 99999999999}}\n");
  EXPECT_EQ(huge.error, huge.path +
                            ":1: health.frame.blank_frames: expected an integer in "
                            "[-2147483648, 2147483647], got 99999999999");
  const Loaded empty = load("");
  EXPECT_EQ(empty.error, empty.path + ": (top level): expected a map, got an empty file");
}

TEST(TuningLoader, OutOfRangeValuesComeFromTheComponentsNamingFileLineAndKey) {
  std::string path;
  std::string e = build_error("runner:\n  obstacle: {stop_m: 9.0}\n", &path);
  EXPECT_EQ(e, path + ":2: runner.obstacle.stop_m: 9 m, expected 0.05 to 5 m");
  e = build_error("health:\n  scan:\n    window_scans: 100\n", &path);
  EXPECT_EQ(e, path + ":3: health.scan.window_scans: 100 scans, expected 1 to 64 scans");
  e = build_error("watch: {scanner_timeout_s: 0}\n", &path);
  EXPECT_EQ(e, path + ":1: watch.scanner_timeout_s: 0 s, expected 0.01 to 10 s");
  e = build_error("limits: {max_yaw_accel_radps2: -1}\n", &path);
  EXPECT_EQ(e, path + ":1: limits.max_yaw_accel_radps2: -1 rad/s^2, expected 0.01 to 50 rad/s^2");
}

TEST(TuningLoader, MissingFile) {
  Tuning t;
  std::string error;
  EXPECT_FALSE(load_tuning("/nonexistent/tuning.yaml", t, error));
  EXPECT_EQ(error, "/nonexistent/tuning.yaml: cannot open");
}

}  // namespace
}  // namespace carril::loader
