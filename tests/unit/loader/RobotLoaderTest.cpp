// Robot description files: the shipped ones load; which sensors are fitted; strict errors.
#include "loader/RobotLoader.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::edit;
using test::read_text;
using test::source_path;
using test::write_file;

const std::string kCampero = read_text(source_path("config/robots/campero.yaml"));
// The preset without its `imu:` line, and the line of a key appended to that.
const std::string kImuLine = [] {
  const std::size_t at = kCampero.find("\nimu: {") + 1;
  return kCampero.substr(at, kCampero.find('\n', at) + 1 - at);
}();
const std::string kNoImu = edit(kCampero, kImuLine, "");
const std::string kAppendedLine =
    std::to_string(std::count(kNoImu.begin(), kNoImu.end(), '\n') + 1);

struct Loaded {
  bool ok = false;
  RobotSpec robot;
  std::string error;
  std::string path;
};

Loaded load(const std::string& text) {
  Loaded l;
  l.path = write_file("robot.yaml", text);
  l.ok = load_robot_preset(l.path, l.robot, l.error);
  return l;
}

TEST(RobotLoader, ShippedRobotsLoadWithEverySensorFitted) {
  for (const char* name : {"campero", "create3", "pioneer3at"}) {
    RobotSpec r;
    std::string error;
    const std::string path = source_path(std::string("config/robots/") + name + ".yaml");
    ASSERT_TRUE(load_robot_preset(path, r, error)) << error;
    EXPECT_EQ(r.preset, name);
    EXPECT_EQ(r.source_path, path);
    EXPECT_TRUE(r.lidar.present);
    EXPECT_TRUE(r.imu.present);
  }
}

TEST(RobotLoader, ARoundBodyIsItsDiameterBothWays) {
  std::string error;
  RobotSpec r;
  ASSERT_TRUE(load_robot_preset(source_path("config/robots/create3.yaml"), r, error)) << error;
  EXPECT_TRUE(r.round_body);
  EXPECT_EQ(r.length_m, r.width_m);
  const Loaded box = load(kCampero);
  ASSERT_TRUE(box.ok) << box.error;
  EXPECT_FALSE(box.robot.round_body);
  const Loaded round = load(edit(kCampero, "mass_kg: 110.0}", "mass_kg: 110.0, shape: round}"));
  EXPECT_FALSE(round.ok);
  EXPECT_NE(round.error.find("body.shape: a round body needs length_m equal to width_m"),
            std::string::npos)
      << round.error;
  const Loaded bad = load(edit(kCampero, "mass_kg: 110.0}", "mass_kg: 110.0, shape: oval}"));
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("body.shape: expected one of box, round"), std::string::npos)
      << bad.error;
}

TEST(RobotLoader, TheGyroSettingsAreRead) {
  const Loaded preset = load(kCampero);
  ASSERT_TRUE(preset.ok) << preset.error;
  EXPECT_TRUE(preset.robot.imu.gyro_heading);
  EXPECT_DOUBLE_EQ(preset.robot.imu.gyro_noise_std_radps, 0.003);
  EXPECT_DOUBLE_EQ(preset.robot.imu.gyro_bias_radps, 0.0005);
  // Without the keys: the heading from the gyro, an ideal one in the simulator.
  const Loaded plain = load(kNoImu + "imu: {present: true}\n");
  ASSERT_TRUE(plain.ok) << plain.error;
  EXPECT_TRUE(plain.robot.imu.gyro_heading);
  EXPECT_EQ(plain.robot.imu.gyro_noise_std_radps, 0.0);
  EXPECT_EQ(plain.robot.imu.gyro_bias_radps, 0.0);
  const Loaded wheels = load(kNoImu + "imu: {present: true, gyro_heading: false}\n");
  ASSERT_TRUE(wheels.ok) << wheels.error;
  EXPECT_FALSE(wheels.robot.imu.gyro_heading);
}

TEST(RobotLoader, ImuAndLidarCanBeNotFitted) {
  const Loaded imu = load(kNoImu + "imu: {present: false}\n");
  ASSERT_TRUE(imu.ok) << imu.error;
  EXPECT_FALSE(imu.robot.imu.present);
  // A lidar that is not fitted needs no mount.
  const std::string lidar_line = kCampero.substr(kCampero.find("lidar: {"));
  const std::string no_lidar =
      edit(kCampero, lidar_line.substr(0, lidar_line.find('\n')), "lidar: {present: false}");
  const Loaded lidar = load(no_lidar);
  ASSERT_TRUE(lidar.ok) << lidar.error;
  EXPECT_FALSE(lidar.robot.lidar.present);
  // A fitted lidar needs all of it.
  const Loaded partial = load(edit(no_lidar, "present: false", "present: true"));
  ASSERT_FALSE(partial.ok);
  EXPECT_NE(partial.error.find("lidar.x_m: missing required key"), std::string::npos)
      << partial.error;
}

TEST(RobotLoader, TheLocalisationModelIsReadWithTheFirmwaresRanges) {
  const Loaded preset = load(kCampero);
  ASSERT_TRUE(preset.ok) << preset.error;
  EXPECT_EQ(preset.robot.localisation.sigma_hit_m, 0.1);
  EXPECT_EQ(preset.robot.localisation.alpha4, 0.05);
  EXPECT_EQ(preset.robot.localisation.surface_distance, true);
  EXPECT_EQ(preset.robot.localisation.search_sigma_hit_m, 0.2);
  // Without the section: nothing set, the firmware's defaults stand.
  const std::string line = kCampero.substr(kCampero.find("\nlocalisation: {") + 1);
  const Loaded none = load(edit(kCampero, line.substr(0, line.find('\n')), ""));
  ASSERT_TRUE(none.ok) << none.error;
  EXPECT_FALSE(none.robot.localisation.sigma_hit_m.has_value());
  EXPECT_FALSE(none.robot.localisation.surface_distance.has_value());
  // A value outside MclConfig::validate()'s range names this file, line and key.
  const Loaded bad = load(edit(kCampero, "sigma_hit_m: 0.1,", "sigma_hit_m: 9,"));
  const std::string at = std::to_string(
      std::count(kCampero.begin(), kCampero.begin() + kCampero.find("\nlocalisation"), '\n') + 2);
  EXPECT_EQ(bad.error,
            bad.path + ":" + at + ": localisation.sigma_hit_m: 9 m, expected 0.005 to 5 m");
  const Loaded key = load(edit(kCampero, "alpha4: 0.05,", "alpha5: 0.05,"));
  EXPECT_NE(key.error.find("localisation.alpha5: unknown key"), std::string::npos) << key.error;
}

TEST(RobotLoader, StrictErrorsNameFileLineAndKey) {
  const Loaded type = load(kNoImu + "imu: {present: yes}\n");
  EXPECT_EQ(type.error,
            type.path + ":" + kAppendedLine + ": imu.present: expected true or false, got \"yes\"");
  const Loaded key = load(kNoImu + "imu: {present: true, rate_hz: 100}\n");
  EXPECT_EQ(key.error, key.path + ":" + kAppendedLine +
                           ": imu.rate_hz: unknown key (allowed: present, gyro_heading, "
                           "gyro_noise_std_radps, gyro_bias_radps)");
  const Loaded noise = load(kNoImu + "imu: {present: true, gyro_noise_std_radps: -0.1}\n");
  EXPECT_EQ(noise.error, noise.path + ":" + kAppendedLine +
                             ": imu.gyro_noise_std_radps: expected a number in [0, 1], got -0.1");
  const Loaded range = load(edit(kCampero, "width: 640", "width: 6400"));
  EXPECT_NE(range.error.find(range.path + ":10: camera.width: expected an integer in [32, 1280], "
                                          "got 6400"),
            std::string::npos)
      << range.error;
  const Loaded missing = load(edit(kCampero, "control_rate_hz: 100\n", ""));
  EXPECT_NE(missing.error.find("control_rate_hz: missing required key"), std::string::npos)
      << missing.error;
}

TEST(RobotLoader, TerrainLimitsAreRequiredAndChecked) {
  const RobotSpec p3 = test::robot("pioneer3at");
  EXPECT_EQ(p3.terrain_limits.max_slope_deg, 19.0);
  EXPECT_EQ(p3.terrain_limits.max_step_up_m, 0.10);
  EXPECT_EQ(p3.terrain_limits.max_step_down_m, 0.15);
  const RobotSpec campero = test::robot("campero");
  EXPECT_EQ(campero.terrain_limits.max_slope_deg, 10.0);
  const std::string line =
      "terrain_limits: {max_slope_deg: 10.0, max_step_up_m: 0.03, "
      "max_step_down_m: 0.08}";
  const Loaded missing = load(edit(kCampero, line, ""));
  EXPECT_NE(missing.error.find("terrain_limits: missing required key"), std::string::npos)
      << missing.error;
  const Loaded partial = load(edit(kCampero, "max_step_up_m: 0.03, ", ""));
  EXPECT_NE(partial.error.find("terrain_limits.max_step_up_m: missing required key"),
            std::string::npos)
      << partial.error;
  const Loaded range = load(edit(kCampero, "max_slope_deg: 10.0", "max_slope_deg: 61"));
  EXPECT_NE(range.error.find("terrain_limits.max_slope_deg: expected a number in [1, 60], got 61"),
            std::string::npos)
      << range.error;
  const Loaded key = load(edit(kCampero, "max_step_down_m: 0.08", "max_step_down_m: 0.08, x: 1"));
  EXPECT_NE(key.error.find("terrain_limits.x: unknown key (allowed: max_slope_deg, max_step_up_m, "
                           "max_step_down_m)"),
            std::string::npos)
      << key.error;
}

}  // namespace
}  // namespace carril::loader
