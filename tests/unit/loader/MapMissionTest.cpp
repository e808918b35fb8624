// A mission file on a known map (map:, localisation:) and the firmware set-up it gives, shared by
// carril_sim and carril_controller (loader/MapMission.hpp).
#include "loader/MapMission.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>

#include "loader/FirmwareConfigBuilder.hpp"
#include "loader/MissionLoader.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::robot;
using test::source_path;
using test::write_file;

struct Loaded {
  bool ok = false;
  MissionSpec mission;
  std::string error;
  std::string path;
};

Loaded load(const std::string& text) {
  Loaded l;
  l.path = write_file("map_mission.yaml", text);
  l.ok = load_mission(l.path, robot("pioneer3at"), l.mission, l.error);
  return l;
}

TEST(MapMission, TheShippedMissionNamesTheHouseRelativeToItsFolder) {
  MissionSpec m;
  std::string error;
  const std::string path = source_path("config/missions/goto_house.yaml");
  ASSERT_TRUE(load_mission(path, robot("pioneer3at"), m, error)) << error;
  EXPECT_EQ(m.type, "goto");
  EXPECT_TRUE(std::filesystem::equivalent(m.map_path, source_path("scenarios/maps/house.yaml")))
      << m.map_path;
  EXPECT_TRUE(m.localisation.has_initial_pose);
  EXPECT_GE(m.goals.size(), 1U);
}

TEST(MapMission, ReadsTheStartAndResolvesTheMapAgainstTheFile) {
  const Loaded l = load(
      "type: goto\nmap: maps/floor.yaml\ngoal: {x: 1, y: 2, yaw_deg: 0}\n"
      "localisation: {initial_pose: {x: 0.5, y: -1.0, yaw_deg: 90}, initial_sigma_xy_m: 0.8,\n"
      "  initial_sigma_yaw_deg: 30, recovery: true}\n");
  ASSERT_TRUE(l.ok) << l.error;
  const MissionSpec& m = l.mission;
  EXPECT_EQ(m.map_path, (std::filesystem::path(l.path).parent_path() / "maps/floor.yaml").string());
  EXPECT_TRUE(m.localisation.has_initial_pose);
  EXPECT_DOUBLE_EQ(m.localisation.initial_pose.x_m, 0.5);
  EXPECT_DOUBLE_EQ(m.localisation.initial_pose.y_m, -1.0);
  EXPECT_DOUBLE_EQ(m.localisation.initial_pose.yaw_deg, 90.0);
  EXPECT_DOUBLE_EQ(m.localisation.initial_sigma_xy_m, 0.8);
  EXPECT_NEAR(m.localisation.initial_sigma_yaw_rad, 30.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_TRUE(m.localisation.recovery);
  EXPECT_FALSE(m.localisation.global);
}

TEST(MapMission, BadKeysAreNamed) {
  // A kidnap is a simulator's event, not a mission's.
  const Loaded kidnap = load(
      "type: goto\nmap: m.yaml\ngoal: {x: 1, y: 2, yaw_deg: 0}\n"
      "localisation: {kidnap: []}\n");
  EXPECT_FALSE(kidnap.ok);
  EXPECT_NE(kidnap.error.find(kidnap.path + ":4: localisation.kidnap: unknown key"),
            std::string::npos)
      << kidnap.error;
  const Loaded no_map =
      load("type: goto\ngoal: {x: 1, y: 2, yaw_deg: 0}\nlocalisation: {global: true}\n");
  EXPECT_FALSE(no_map.ok);
  EXPECT_NE(no_map.error.find("localisation: expected localisation only with a map:"),
            std::string::npos)
      << no_map.error;
  const Loaded both = load(
      "type: goto\nmap: m.yaml\ngoal: {x: 1, y: 2, yaw_deg: 0}\n"
      "localisation: {global: true, initial_pose: {x: 0, y: 0, yaw_deg: 0}}\n");
  EXPECT_FALSE(both.ok);
  EXPECT_NE(both.error.find("localisation.global: expected no initial_pose with global: true"),
            std::string::npos)
      << both.error;
  const Loaded coverage = load("type: coverage\nmode: systematic\n");
  EXPECT_FALSE(coverage.ok);
  EXPECT_NE(coverage.error.find("map: expected a map file: a systematic coverage mission plans"),
            std::string::npos)
      << coverage.error;
  // The vacuum baseline is blind to the map: it needs none.
  EXPECT_TRUE(load("type: coverage\nmode: vacuum\n").ok);
  // follow_line keeps to its tape: no map key.
  const Loaded line = load("type: follow_line\nstrategy: pid\nline_color: white\nmap: m.yaml\n");
  EXPECT_FALSE(line.ok);
  EXPECT_NE(line.error.find("map: unknown key"), std::string::npos) << line.error;
}

TEST(MapMission, ConfiguresLocalisationOnTheMap) {
  const Loaded l = load(
      "type: goto\nmap: m.yaml\ngoal: {x: 1, y: 2, yaw_deg: 0}\n"
      "localisation: {initial_pose: {x: 0.5, y: -1.0, yaw_deg: 90}}\n");
  ASSERT_TRUE(l.ok) << l.error;
  const RobotSpec r = robot("pioneer3at");
  BuildResult b = build_firmware_config(r, l.mission);
  ASSERT_TRUE(b.ok) << b.error;
  fw::FirmwareConfig c = b.config;
  EXPECT_FALSE(c.localisation.enabled);
  configure_for_map(r, l.mission.localisation, {9.0, 9.0, 0.0}, c);
  EXPECT_TRUE(c.localisation.enabled);
  EXPECT_FALSE(c.mapping.terrain);
  EXPECT_DOUBLE_EQ(c.localisation.initial_pose.x, 0.5);
  EXPECT_DOUBLE_EQ(c.localisation.initial_pose.y, -1.0);
  EXPECT_NEAR(c.localisation.initial_pose.yaw, std::numbers::pi / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(c.localisation.mcl.laser_max_range_m, r.lidar.range_max_m);
  // Recovery off by default (AMCL's): no random injection.
  EXPECT_EQ(c.localisation.mcl.alpha_fast, 0.0);
  EXPECT_EQ(c.localisation.mcl.alpha_slow, 0.0);
  // Told where it starts, it waits still while not localised.
  EXPECT_FALSE(c.localisation.search_while_unlocalised);
  EXPECT_EQ(c.runner.lost_turn_radps, 0.0);
  EXPECT_EQ(c.runner.lost_explore.speed_mps, 0.0);
  // Held unlocalised for a minute, it gives up with not_localised (the runner's default waits).
  EXPECT_EQ(c.runner.max_unlocalised_s, 60.0);
  EXPECT_EQ(b.config.runner.max_unlocalised_s, 0.0);

  // No initial pose: the given default; recovery on keeps MclConfig's rates.
  LocalisationStartSpec start;
  start.recovery = true;
  fw::FirmwareConfig d = b.config;
  configure_for_map(r, start, {9.0, 8.0, 0.25}, d);
  EXPECT_DOUBLE_EQ(d.localisation.initial_pose.x, 9.0);
  EXPECT_DOUBLE_EQ(d.localisation.initial_pose.y, 8.0);
  EXPECT_DOUBLE_EQ(d.localisation.initial_pose.yaw, 0.25);
  EXPECT_GT(d.localisation.mcl.alpha_fast, d.localisation.mcl.alpha_slow);
  EXPECT_GT(d.localisation.mcl.alpha_slow, 0.0);
  // A robot that may be carried elsewhere searches the map and looks round while lost.
  EXPECT_TRUE(d.localisation.search_while_unlocalised);
  EXPECT_GT(d.runner.lost_turn_radps, 0.0);
  // Still lost after a whole turn, it drives legs toward open space, at a walking pace.
  EXPECT_GT(d.runner.lost_explore.speed_mps, 0.0);
  EXPECT_LE(d.runner.lost_explore.speed_mps, 0.3);
  EXPECT_TRUE(d.runner.validate().is_ok()) << d.runner.validate().message();
}

// How long the robot may stay unlocalised is the mission's to say (a large site may need more
// than the minute); 0 waits for ever. Out of range is refused, naming the key.
TEST(MapMission, TheMissionSetsHowLongTheRobotMayStayUnlocalised) {
  const std::string head = "type: goto\nmap: m.yaml\ngoal: {x: 1, y: 2, yaw_deg: 0}\n";
  const RobotSpec r = robot("pioneer3at");
  for (const auto& [text, want] : {std::pair<const char*, double>{"150", 150.0}, {"0", 0.0}}) {
    const Loaded l = load(head + "localisation: {global: true, max_unlocalised_s: " + text + "}\n");
    ASSERT_TRUE(l.ok) << l.error;
    BuildResult b = build_firmware_config(r, l.mission);
    ASSERT_TRUE(b.ok) << b.error;
    configure_for_map(r, l.mission.localisation, {}, b.config);
    EXPECT_EQ(b.config.runner.max_unlocalised_s, want) << text;
    EXPECT_TRUE(b.config.runner.validate()) << text;
  }
  for (const char* bad : {"-1", "1e6", "soon"}) {
    const Loaded l = load(head + "localisation: {max_unlocalised_s: " + bad + "}\n");
    EXPECT_FALSE(l.ok) << bad;
    EXPECT_NE(l.error.find("localisation.max_unlocalised_s"), std::string::npos) << l.error;
  }
}

}  // namespace
}  // namespace carril::loader
