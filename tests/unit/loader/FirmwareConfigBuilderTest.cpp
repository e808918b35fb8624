// build_firmware_config: the mapping the simulator made before the builder, exactly; the robot
// target's files; sensors fitted or not; rejections traced to the file and key.
#include "loader/FirmwareConfigBuilder.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "loader/ColorThreshold.hpp"
#include "loader/TuningLoader.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::edit;
using test::expect_same;
using test::robot;
using test::source_path;
using test::write_file;

// What carril::sim::firmware_config (host_sim/app/SimTopology.cpp) did before the builder, with
// host_sim's drive_geometry and camera_mount inlined, kept as it was: the reference the builder
// must reproduce bit for bit.
fw::FirmwareConfig old_sim_mapping(const RobotSpec& r, const MissionSpec& m) {
  constexpr double kDeg = M_PI / 180.0;
  fw::FirmwareConfig c;
  c.rate_hz = r.control_rate_hz;
  c.drive.type =
      r.drive == DriveType::Mecanum ? fw::DriveType::Mecanum : fw::DriveType::Differential;
  c.drive.wheel_radius_m = r.wheel_radius_m;
  c.drive.wheelbase_m = r.wheelbase_m;
  c.drive.track_m = r.track_m;
  c.footprint_length_m = r.length_m;
  c.footprint_width_m = r.width_m;
  c.limits.max_speed_mps = r.limits.max_speed_mps;
  c.limits.max_yaw_rate_radps = r.limits.max_yaw_rate_radps;
  c.limits.max_accel_mps2 = r.limits.max_accel_mps2;
  c.limits.max_wheel_speed_radps = r.limits.max_wheel_speed_radps;
  c.camera.camera.x_m = r.camera.x_m;
  c.camera.camera.y_m = r.camera.y_m;
  c.camera.camera.z_m = r.camera.z_m;
  c.camera.camera.tilt_rad = r.camera.tilt_deg * kDeg;
  c.camera.camera.hfov_rad = r.camera.hfov_deg * kDeg;
  c.camera.camera.width = r.camera.width;
  c.camera.camera.height = r.camera.height;
  c.camera.rate_hz = r.camera.rate_hz;
  c.lidar.present = true;
  c.lidar.x_m = r.lidar.x_m;
  c.lidar.y_m = r.lidar.y_m;
  c.lidar.yaw_rad = r.lidar.yaw_deg * kDeg;
  c.lidar.rate_hz = r.lidar.rate_hz;
  c.lidar.reliable_range_m = r.lidar.range_max_m;
  c.runner.check.round_body = r.round_body;
  c.watch.imu_present = true;
  c.camera.detector.line = detector_threshold(m.line_color_name, m.line_color);
  c.camera.detector.end = detector_threshold(m.end_color_name, m.end_color);
  fw::StrategyConfig& st = c.follow_line.strategy;
  st.strategy = m.strategy == "line_priority" ? fw::Strategy::LinePriority
                : m.strategy == "pid"         ? fw::Strategy::Pid
                                              : fw::Strategy::Marks;
  st.speed_mps = m.speed_mps;
  st.pid_straight.speed_mps = m.speed_mps;
  st.pid_curve.speed_mps = 0.8 * m.speed_mps;
  c.follow_line.behavior.init_timeout_s = 3.0;
  fw::apply_sensor_rates(c);
  return c;
}

MissionSpec mission(const std::string& strategy, double speed, const std::string& line = "white",
                    Rgb line_rgb = {255, 255, 255}) {
  MissionSpec m;
  m.strategy = strategy;
  m.speed_mps = speed;
  m.line_color_name = line;
  m.line_color = line_rgb;
  return m;
}

TEST(FirmwareConfigBuilder, ReproducesTheSimulatorsMappingForBothPresets) {
  struct Case {
    const char* preset;
    MissionSpec m;
  };
  const Case cases[] = {
      {"campero", mission("line_priority", 0.5)},
      {"campero", mission("marks", 0.8, "[255, 0, 0]", {255, 0, 0})},
      {"campero", mission("pid", 0.37, "red", {255, 0, 0})},
      {"pioneer3at", mission("marks", 0.5)},
      {"pioneer3at", mission("pid", 0.61, "[10, 200, 30]", {10, 200, 30})},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(std::string(k.preset) + " " + k.m.strategy);
    const RobotSpec r = robot(k.preset);
    const BuildResult b = build_firmware_config(r, k.m);
    ASSERT_TRUE(b.ok) << b.error;
    EXPECT_EQ(b.error, "");
    EXPECT_EQ(b.firmware_error, "");
    expect_same(b.config, old_sim_mapping(r, k.m));
  }
}

TEST(FirmwareConfigBuilder, TheRobotTargetsFilesBuild) {
  const RobotSpec r = robot("campero");
  MissionSpec m;
  std::string error;
  ASSERT_TRUE(load_mission(source_path("config/missions/follow_line.yaml"), r, m, error)) << error;
  Tuning t;
  ASSERT_TRUE(load_tuning(source_path("config/tuning/default.yaml"), t, error)) << error;
  const BuildResult plain = build_firmware_config(r, m);
  ASSERT_TRUE(plain.ok) << plain.error;
  // The shipped tuning file writes out the defaults: it changes nothing.
  const BuildResult tuned = build_firmware_config(r, m, &t);
  ASSERT_TRUE(tuned.ok) << tuned.error;
  EXPECT_FALSE(t.settings.empty());
  expect_same(tuned.config, plain.config);
  EXPECT_EQ(plain.config.follow_line.strategy.strategy, fw::Strategy::LinePriority);
  EXPECT_TRUE(plain.config.lidar.present);
  EXPECT_TRUE(plain.config.watch.imu_present);
  EXPECT_TRUE(plain.config.gyro_heading);
}

TEST(FirmwareConfigBuilder, SensorsNotFittedAreTold) {
  RobotSpec r = robot("pioneer3at");
  r.lidar.present = false;
  r.imu.present = false;
  const BuildResult b = build_firmware_config(r, mission("pid", 0.5));
  ASSERT_TRUE(b.ok) << b.error;
  EXPECT_FALSE(b.config.lidar.present);
  EXPECT_FALSE(b.config.watch.imu_present);
  EXPECT_FALSE(b.config.gyro_heading);  // no IMU, no gyro heading, whatever the file says
  r.imu.present = true;
  r.imu.gyro_heading = false;
  const BuildResult wheels = build_firmware_config(r, mission("pid", 0.5));
  ASSERT_TRUE(wheels.ok) << wheels.error;
  EXPECT_TRUE(wheels.config.watch.imu_present);
  EXPECT_FALSE(wheels.config.gyro_heading);
}

// The preset's ranges lie inside the firmware's: any robot file the loader accepts gives a
// configuration the firmware accepts (a camera faster than the control loop is processed every
// tick; a camera looking straight down is a valid mount).
TEST(FirmwareConfigBuilder, EveryValueThePresetAcceptsTheFirmwareAcceptsToo) {
  RobotSpec r = robot("campero");
  r.camera.rate_hz = 240.0;  // the preset's maximum, faster than the 100 Hz control rate
  r.camera.tilt_deg = 90.0;
  r.camera.hfov_deg = 20.0;  // the preset's minimum
  r.control_rate_hz = 10.0;
  r.lidar.rate_hz = 100.0;
  r.limits.max_yaw_rate_radps = 10.0;  // the IMU limit derived from it, 40 rad/s, is in range
  const BuildResult b = build_firmware_config(r, mission("marks", 0.5));
  EXPECT_TRUE(b.ok) << b.error;
}

// A coverage mission's lanes are driven at the mission's speed (the score's lower bound is taken
// at it), its transits at transit_speed_mps (the mission's speed unless given), both turning no
// faster than the robot; its wall clearance and lane overlap are passed on.
TEST(FirmwareConfigBuilder, CoverageFollowersDriveTheMissionsSpeed) {
  MissionSpec m = mission("marks", 0.3);
  m.type = "coverage";
  m.wall_clearance_m = 0.05;
  RobotSpec r = robot("pioneer3at");
  r.limits.max_yaw_rate_radps = 1.2;
  const BuildResult b = build_firmware_config(r, m);
  ASSERT_TRUE(b.ok) << b.error;
  const fw::CoverageConfig& k = b.config.coverage;
  EXPECT_EQ(k.speed_mps, 0.3);
  EXPECT_EQ(k.sweep.cruise_speed_mps, 0.3);
  EXPECT_EQ(k.transit_pursuit.cruise_speed_mps, 0.3);
  EXPECT_EQ(k.sweep.max_yaw_rate_radps, 1.2);
  EXPECT_LE(k.transit_pursuit.max_yaw_rate_radps, 1.2);
  EXPECT_EQ(k.wall_clearance_m, 0.05);
  EXPECT_EQ(k.transit_speed_mps, 0.3);
  EXPECT_DOUBLE_EQ(k.lane_overlap, 0.1);
  // Transits at their own speed, lanes at the mission's; the lanes' overlap passed on.
  m.transit_speed_mps = 0.6;
  m.lane_overlap = 0.05;
  const BuildResult fast = build_firmware_config(r, m);
  ASSERT_TRUE(fast.ok) << fast.error;
  EXPECT_EQ(fast.config.coverage.transit_speed_mps, 0.6);
  EXPECT_EQ(fast.config.coverage.transit_pursuit.cruise_speed_mps, 0.6);
  EXPECT_EQ(fast.config.coverage.sweep.cruise_speed_mps, 0.3);
  EXPECT_DOUBLE_EQ(fast.config.coverage.lane_overlap, 0.05);
}

// The lanes' turns brake for the robot's yaw acceleration: the limits', a tuning file's when it
// sets them (applied after the mission's followers are set up), at the control period.
TEST(FirmwareConfigBuilder, CoverageSweepBrakesForTheYawAccelerationTheTuningSets) {
  MissionSpec m = mission("marks", 0.3);
  m.type = "coverage";
  const BuildResult plain = build_firmware_config(robot("pioneer3at"), m);
  ASSERT_TRUE(plain.ok) << plain.error;
  EXPECT_EQ(plain.config.coverage.sweep.max_yaw_accel_radps2,
            plain.config.limits.max_yaw_accel_radps2);
  EXPECT_GT(plain.config.coverage.sweep.max_yaw_accel_radps2, 0.0);
  EXPECT_DOUBLE_EQ(plain.config.coverage.sweep.period_s, 1.0 / plain.config.rate_hz);
  const std::string path = write_file("yaw.yaml", "limits: {max_yaw_accel_radps2: 2.5}\n");
  Tuning t;
  std::string error;
  ASSERT_TRUE(load_tuning(path, t, error)) << error;
  const BuildResult tuned = build_firmware_config(robot("pioneer3at"), m, &t);
  ASSERT_TRUE(tuned.ok) << tuned.error;
  EXPECT_EQ(tuned.config.coverage.sweep.max_yaw_accel_radps2, 2.5);
  // Other missions leave the lane follower as it is.
  const BuildResult line = build_firmware_config(robot("pioneer3at"), mission("marks", 0.3));
  ASSERT_TRUE(line.ok) << line.error;
  EXPECT_EQ(line.config.coverage.sweep.max_yaw_accel_radps2, 0.0);
}

TEST(FirmwareConfigBuilder, UnknownStrategyIsRejected) {
  MissionSpec m = mission("zigzag", 0.5);
  m.source_path = "m.yaml";
  const BuildResult b = build_firmware_config(robot("campero"), m);
  ASSERT_FALSE(b.ok);
  EXPECT_EQ(b.error, "m.yaml: strategy: expected line_priority, marks or pid, got \"zigzag\"");
}

TEST(FirmwareConfigBuilder, TuningOutOfRangeNamesTheTuningFileLineAndKey) {
  const std::string path =
      write_file("range.yaml", "detector:\n  decimation: 3\nhealth:\n  scan: {window_scans: 7}\n");
  Tuning t;
  std::string error;
  ASSERT_TRUE(load_tuning(path, t, error)) << error;  // types are fine; the range is validate()'s
  const BuildResult b = build_firmware_config(robot("campero"), mission("marks", 0.5), &t);
  ASSERT_FALSE(b.ok);
  EXPECT_EQ(b.error, path + ":2: detector.decimation: expected 1, 2 or 4");
  EXPECT_EQ(b.firmware_error, "detector.decimation: expected 1, 2 or 4");
}

TEST(FirmwareConfigBuilder, TuningOverridesWhatTheRatesDerive) {
  const std::string path =
      write_file("derived.yaml",
                 "health: {scan: {window_scans: 7}, imu: {max_yaw_rate_radps: 9}}\n"
                 "watch: {camera_timeout_s: 0.3}\nlimits: {max_yaw_accel_radps2: 2.5}\n");
  Tuning t;
  std::string error;
  ASSERT_TRUE(load_tuning(path, t, error)) << error;
  const BuildResult plain = build_firmware_config(robot("campero"), mission("marks", 0.5));
  const BuildResult b = build_firmware_config(robot("campero"), mission("marks", 0.5), &t);
  ASSERT_TRUE(b.ok) << b.error;
  EXPECT_EQ(plain.config.lidar.health.window_scans, 5);  // 20 Hz x 0.25 s
  EXPECT_EQ(b.config.lidar.health.window_scans, 7);
  EXPECT_EQ(b.config.watch.imu.max_yaw_rate_radps, 9.0);
  EXPECT_EQ(b.config.watch.camera_timeout_s, 0.3);
  EXPECT_EQ(b.config.limits.max_yaw_accel_radps2, 2.5);
  EXPECT_EQ(b.config.watch.scanner_timeout_s, plain.config.watch.scanner_timeout_s);
}

}  // namespace
}  // namespace carril::loader
