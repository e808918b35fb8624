// The scenario sections of missions on a map: localisation (needs a map; initial pose or global,
// kidnaps in time order), odometry drift, and the mission types goto with goals, waypoints and
// coverage; each bad input names its key.
#include <gtest/gtest.h>

#include <string>

#include "tests/unit/scenario/ScenarioTestUtil.hpp"

namespace carril::sim {
namespace {

const std::string kHead = R"(name: on_map
duration_s: 10
map: maps/house.yaml
robot: {preset: pioneer3at}
)";

LoadResult load_in_scenarios(const std::string& text) {
  // As a file in scenarios/ (so maps/house.yaml resolves); never written there.
  return load_scenario_text(text, std::string(CARRIL_SOURCE_DIR) + "/scenarios/on_map.yaml",
                            test::robots_dir());
}

// The load failed with a message naming this scenario file and holding every fragment.
::testing::AssertionResult fails_naming(const LoadResult& r,
                                        std::initializer_list<const char*> fragments) {
  if (r.ok) return ::testing::AssertionFailure() << "loaded";
  if (r.error.rfind(std::string(CARRIL_SOURCE_DIR) + "/scenarios/on_map.yaml:", 0) != 0) {
    return ::testing::AssertionFailure() << "no file name: " << r.error;
  }
  for (const char* f : fragments) {
    if (r.error.find(f) == std::string::npos) {
      return ::testing::AssertionFailure() << "lacks '" << f << "': " << r.error;
    }
  }
  return ::testing::AssertionSuccess();
}

const std::string kGoto = "mission: {type: goto, goal: {x: 3.6, y: 1.4, yaw_deg: 90}}\n";

TEST(ScenarioMissionsOnMap, ReadsLocalisationKidnapsAndOdometryDrift) {
  const LoadResult r = load_in_scenarios(kHead + kGoto + R"(localisation:
  initial_pose: {x: 0.5, y: -0.5, yaw_deg: 30}
  initial_sigma_xy_m: 1.0
  initial_sigma_yaw_deg: 40
  recovery: true
  max_unlocalised_s: 90
  kidnap:
    - {t_s: 5, x: 1.3, y: -2.05, yaw_deg: 90}
    - {t_s: 9, x: 0, y: 0, yaw_deg: 0}
odometry: {wheel_radius_error: 0.02, slip: 0.05}
)");
  ASSERT_TRUE(r.ok) << r.error;
  const LocalisationSpec& l = r.scenario.localisation;
  ASSERT_TRUE(l.initial_pose.has_value());
  EXPECT_DOUBLE_EQ(l.initial_pose->x, 0.5);
  EXPECT_NEAR(l.initial_pose->yaw_rad, 0.5235987755982988, 1e-12);
  EXPECT_DOUBLE_EQ(l.initial_sigma_xy_m, 1.0);
  EXPECT_TRUE(l.recovery);
  EXPECT_DOUBLE_EQ(l.max_unlocalised_s, 90.0);
  ASSERT_EQ(l.kidnaps.size(), 2U);
  EXPECT_DOUBLE_EQ(l.kidnaps[0].t_s, 5.0);
  EXPECT_DOUBLE_EQ(l.kidnaps[0].to.y, -2.05);
  EXPECT_DOUBLE_EQ(r.scenario.odometry.wheel_radius_error, 0.02);
  EXPECT_DOUBLE_EQ(r.scenario.odometry.slip, 0.05);
}

TEST(ScenarioMissionsOnMap, BadLocalisationAndOdometryNameTheirKey) {
  // Localisation needs a map.
  EXPECT_TRUE(test::fails_with(test::kMinimalYaml + "localisation: {global: true}\n",
                               {"localisation", "a map"}));
  EXPECT_TRUE(fails_naming(
      load_in_scenarios(kHead + kGoto +
                        "localisation: {global: true, initial_pose: {x: 0, y: 0, yaw_deg: 0}}\n"),
      {"global", "no initial_pose"}));
  EXPECT_TRUE(fails_naming(
      load_in_scenarios(kHead + kGoto +
                        "localisation:\n  kidnap:\n    - {t_s: 5, x: 0, y: 0, yaw_deg: 0}\n"
                        "    - {t_s: 4, x: 0, y: 0, yaw_deg: 0}\n"),
      {"kidnap", "increasing t_s"}));
  EXPECT_TRUE(fails_naming(load_in_scenarios(kHead + kGoto + "localisation: {sigma: 1}\n"),
                           {"sigma", "unknown key"}));
  EXPECT_TRUE(
      fails_naming(load_in_scenarios(kHead + kGoto + "odometry: {wheel_radius_error: 0.5}\n"),
                   {"wheel_radius_error"}));
}

TEST(ScenarioMissionsOnMap, GotoWithGoalsWaypointsAndCoverage) {
  LoadResult r = load_in_scenarios(kHead + R"(mission:
  type: goto
  goals:
    - {x: -2.6, y: -1.55, yaw_deg: 0}
    - {x: 3.6, y: 1.4, yaw_deg: 90}
)");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.scenario.mission.goals.size(), 2U);
  EXPECT_DOUBLE_EQ(r.scenario.mission.goals[1].yaw_deg, 90.0);
  r = load_in_scenarios(kHead +
                        "mission: {type: waypoints, targets: [[1, 0], [2, 1]], laps: 2, "
                        "reach_radius_m: 0.3}\n");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.scenario.mission.targets.size(), 2U);
  EXPECT_EQ(r.scenario.mission.laps, 2);
  r = load_in_scenarios(kHead +
                        "mission: {type: coverage, mode: vacuum, tool_width_m: 0.4, "
                        "max_time_s: 300, area: [[-1, -1], [1, -1], [1, 1]]}\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.mission.coverage_mode, "vacuum");
  EXPECT_DOUBLE_EQ(r.scenario.mission.tool_width_m, 0.4);
  EXPECT_EQ(r.scenario.mission.area.size(), 3U);
  EXPECT_EQ(r.scenario.mission.transit_speed_mps, 0.0);  // the mission's speed
  EXPECT_DOUBLE_EQ(r.scenario.mission.lane_overlap, 0.1);
  r = load_in_scenarios(kHead +
                        "mission: {type: coverage, transit_speed_mps: 0.7, lane_overlap: 0.05}\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_DOUBLE_EQ(r.scenario.mission.transit_speed_mps, 0.7);
  EXPECT_DOUBLE_EQ(r.scenario.mission.lane_overlap, 0.05);
}

TEST(ScenarioMissionsOnMap, BadMissionKeysAreNamed) {
  const std::string both =
      "mission: {type: goto, goal: {x: 1, y: 0, yaw_deg: 0}, goals: [{x: 1, y: 0, yaw_deg: 0}]}\n";
  EXPECT_TRUE(fails_naming(load_in_scenarios(kHead + both), {"goal or goals", "both"}));
  EXPECT_TRUE(fails_naming(load_in_scenarios(kHead + "mission: {type: goto, goals: []}\n"),
                           {"goals", "1 to 16 goals"}));
  EXPECT_TRUE(
      fails_naming(load_in_scenarios(kHead + "mission: {type: waypoints, targets: [[1, 0, 2]]}\n"),
                   {"a point [x, y]"}));
  EXPECT_TRUE(fails_naming(load_in_scenarios(kHead + "mission: {type: coverage, mode: mopping}\n"),
                           {"mode"}));
  EXPECT_TRUE(
      fails_naming(load_in_scenarios(kHead + "mission: {type: coverage, area: [[0, 0], [1, 1]]}\n"),
                   {"area", "3 to 16 corners"}));
  // Issue 46 item 8: a bow tie (edges crossing) or corners on one line have no inside to cover.
  EXPECT_TRUE(fails_naming(
      load_in_scenarios(kHead +
                        "mission: {type: coverage, area: [[0, 0], [2, 2], [2, 0], [0, 2]]}\n"),
      {"area: expected the corners of a simple polygon", "edge 1-2 meeting edge 3-4"}));
  EXPECT_TRUE(fails_naming(
      load_in_scenarios(kHead + "mission: {type: coverage, area: [[0, 0], [1, 1], [2, 2]]}\n"),
      {"area: expected the corners of a polygon with an area", "corners on one line"}));
  // A concave one is fine.
  EXPECT_TRUE(load_in_scenarios(kHead + "mission: {type: coverage, area: [[-1, -1], [1, -1], "
                                        "[1, 1], [0, 0], [-1, 1]]}\n")
                  .ok);
  // The transits may go as fast as the robot (pioneer3at: 0.7 m/s), no faster.
  EXPECT_TRUE(
      fails_naming(load_in_scenarios(kHead + "mission: {type: coverage, transit_speed_mps: 0.8}\n"),
                   {"transit_speed_mps", "max_speed_mps = 0.7", "0.8"}));
  EXPECT_TRUE(
      fails_naming(load_in_scenarios(kHead + "mission: {type: coverage, lane_overlap: 0.6}\n"),
                   {"lane_overlap", "[0, 0.5]"}));
}

}  // namespace
}  // namespace carril::sim
