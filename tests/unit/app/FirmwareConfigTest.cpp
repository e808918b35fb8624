// FirmwareConfig: every component's config is checked at init, in every build type, and an error
// names the field, the value, its unit and the range; apply_sensor_rates derives what follows
// from the sensor rates.
#include "firmware/app/FirmwareConfig.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

namespace carril::fw {
namespace {

struct Case {
  const char* name;
  std::function<void(FirmwareConfig&)> spoil;
  const char* message;  // expected in the error
};

TEST(FirmwareConfigTest, DefaultsAreValid) {
  FirmwareConfig c;
  apply_sensor_rates(c);
  EXPECT_TRUE(c.validate().is_ok()) << c.validate().message();
}

TEST(FirmwareConfigTest, EachBadFieldIsNamedWithItsUnitAndRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Case cases[] = {
      {"rate", [](FirmwareConfig& c) { c.rate_hz = 0.0; },
       "robot.control_rate_hz: 0 Hz, expected 10 to 1000 Hz"},
      {"nan rate", [nan](FirmwareConfig& c) { c.rate_hz = nan; }, "robot.control_rate_hz: nan Hz"},
      {"wheel", [](FirmwareConfig& c) { c.drive.wheel_radius_m = -0.1; },
       "drive.wheel_radius_m: -0.1 m, expected 0.01 to 1 m"},
      {"limits", [](FirmwareConfig& c) { c.limits.max_speed_mps = 50.0; },
       "limits.max_speed_mps: 50 m/s, expected 0.05 to 5 m/s"},
      {"camera tilt", [](FirmwareConfig& c) { c.camera.camera.tilt_rad = 2.0; },
       "camera.tilt_rad: 2 rad"},
      {"camera rate", [](FirmwareConfig& c) { c.camera.rate_hz = 0.0; },
       "camera.rate_hz: 0 Hz, expected 1 to 1000 Hz"},
      {"decimation", [](FirmwareConfig& c) { c.camera.detector.decimation = 3; },
       "detector.decimation: expected 1, 2 or 4"},
      {"scan window", [](FirmwareConfig& c) { c.lidar.health.window_scans = 0; },
       "health.scan.window_scans: 0 scans, expected 1 to 64 scans"},
      {"timeout", [](FirmwareConfig& c) { c.watch.camera_timeout_s = 0.0; },
       "watch.camera_timeout_s: 0 s"},
      {"stop", [](FirmwareConfig& c) { c.runner.obstacle.stop_m = 9.0; },
       "runner.obstacle.stop_m: 9 m, expected 0.05 to 5 m"},
      {"lost frames", [](FirmwareConfig& c) { c.follow_line.behavior.lost_frames = 0; },
       "behavior.lost_frames: 0 frames, expected 1 to 100 frames"},
      {"avoid", [](FirmwareConfig& c) { c.follow_line.behavior.avoid.speed_mps = 0.0; },
       "behavior.avoid.speed_mps: 0 m/s"},
      {"speed", [](FirmwareConfig& c) { c.follow_line.strategy.speed_mps = -1.0; },
       "strategy.speed_mps: -1 m/s"},
      {"pid", [](FirmwareConfig& c) { c.follow_line.strategy.pid_curve.kp = -1.0; },
       "strategy.pid_curve.kp: -1 rad/s per unit error, expected 0 to 100 rad/s per unit error"},
  };
  for (const Case& k : cases) {
    FirmwareConfig c;
    apply_sensor_rates(c);
    k.spoil(c);
    const Status s = c.validate();
    ASSERT_FALSE(s.is_ok()) << k.name;
    EXPECT_NE(std::string(s.message()).find(k.message), std::string::npos)
        << k.name << ": " << s.message();
  }
}

TEST(FirmwareConfigTest, AnAbsentLidarIsNotChecked) {
  FirmwareConfig c;
  apply_sensor_rates(c);
  c.lidar.present = false;
  c.lidar.x_m = 100.0;
  EXPECT_TRUE(c.validate().is_ok()) << c.validate().message();
  c.lidar.present = true;
  EXPECT_FALSE(c.validate().is_ok());
}

// Issue 46 item 1: a top speed whose stop does not fit what the lidar sees reliably, or a
// configured protective field, is refused with both distances; within them it is accepted.
TEST(FirmwareConfigTest, ATopSpeedWhoseFieldsTheLidarCannotCoverIsRefused) {
  FirmwareConfig c;
  c.limits.max_speed_mps = 1.5;
  c.lidar.reliable_range_m = 20.0;
  apply_sensor_rates(c);
  ASSERT_TRUE(c.validate().is_ok()) << c.validate().message();
  c.lidar.reliable_range_m = 3.0;
  Status s = c.validate();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message())
                .find("robot.limits.max_speed_mps: 1.5 m/s needs its warning "
                      "field to reach"),
            std::string::npos)
      << s.message();
  EXPECT_NE(std::string(s.message()).find("beyond lidar.reliable_range_m 3 m"), std::string::npos)
      << s.message();
  c.lidar.reliable_range_m = 20.0;
  c.runner.fields.max_field_m = 0.5;  // a scanner whose largest field is 0.5 m
  s = c.validate();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("longer than runner.fields.max_field_m 0.5 m"),
            std::string::npos)
      << s.message();
  c.limits.max_speed_mps = 0.3;  // its stop fits 0.5 m
  EXPECT_TRUE(c.validate().is_ok()) << c.validate().message();
}

TEST(FirmwareConfigTest, SensorRatesSetTimeoutsAndHealthWindows) {
  FirmwareConfig c;
  c.camera.rate_hz = 30.0;
  c.lidar.rate_hz = 20.0;
  c.limits.max_yaw_rate_radps = 1.5;
  apply_sensor_rates(c);
  EXPECT_DOUBLE_EQ(c.watch.camera_timeout_s, 0.2);   // 3 frames is 0.1 s: at least 0.2 s
  EXPECT_DOUBLE_EQ(c.watch.scanner_timeout_s, 0.5);  // 5 scans is 0.25 s: at least 0.5 s
  EXPECT_EQ(c.lidar.health.window_scans, 5);         // 0.25 s of scans
  EXPECT_EQ(c.camera.health.blank_frames, 6);        // 0.2 s of frames
  EXPECT_DOUBLE_EQ(c.watch.imu.max_yaw_rate_radps, 6.0);
  c.camera.rate_hz = 5.0;
  c.lidar.rate_hz = 5.0;
  apply_sensor_rates(c);
  EXPECT_DOUBLE_EQ(c.watch.camera_timeout_s, 0.6);
  EXPECT_DOUBLE_EQ(c.watch.scanner_timeout_s, 1.0);
  EXPECT_EQ(c.lidar.health.window_scans, 2);
  EXPECT_EQ(c.camera.health.blank_frames, 2);
}

}  // namespace
}  // namespace carril::fw
