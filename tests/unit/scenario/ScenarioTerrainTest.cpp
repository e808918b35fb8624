// The terrain keys: ramps with a second section, a top and an optional descent; raised and
// sunken steps; trenches; obstacle heights; the robot's terrain_limits override. Each new error
// kind names the file, the line and the key.
#include <gtest/gtest.h>

#include "host_sim/scenario/ScenarioLoader.hpp"
#include "tests/unit/scenario/ScenarioTestUtil.hpp"

namespace carril::sim {
namespace {

using test::edit;
using test::fails_with;
using test::kMinimalYaml;
using test::load;

const std::string kTerrainYaml = kMinimalYaml + R"(obstacles:
  - {shape: box, x: 5, y: 5, size_m: [1, 1], height_m: 0.5}
  - {shape: cylinder, x: 8, y: 5, radius_m: 0.3}
terrain:
  - {type: ramp, x: 2, y: 5, length_m: 1.5, width_m: 1, angle_deg: 5, angle2_deg: 11, length2_m: 1, top_m: 0.5, descend: false}
  - {type: step, x: 6, y: 8, length_m: 2, width_m: 1, height_m: -0.2}
  - {type: trench, x: 9, y: 8, yaw_deg: 90, length_m: 3, width_m: 0.4, depth_m: 0.3}
)";

TEST(ScenarioTerrain, NewKeysParse) {
  const LoadResult r = load(kTerrainYaml);
  ASSERT_TRUE(r.ok) << r.error;
  const Scenario& s = r.scenario;
  EXPECT_EQ(s.obstacles[0].height_m, 0.5);
  EXPECT_EQ(s.obstacles[1].height_m, 1.0);  // default: a 1 m tall obstacle
  ASSERT_EQ(s.terrain.size(), 3U);
  const TerrainSpec& ramp = s.terrain[0];
  EXPECT_EQ(ramp.angle2_deg, 11.0);
  EXPECT_EQ(ramp.length2_m, 1.0);
  EXPECT_EQ(ramp.top_m, 0.5);
  EXPECT_FALSE(ramp.descend);
  EXPECT_DOUBLE_EQ(ramp.footprint_length_m(), 1.5 + 1.0 + 0.5);
  EXPECT_EQ(s.terrain[1].height_m, -0.2);
  EXPECT_EQ(s.terrain[2].type, TerrainType::Trench);
  EXPECT_EQ(s.terrain[2].depth_m, 0.3);
  EXPECT_EQ(s.terrain[2].footprint_length_m(), 3.0);
  // Defaults of a plain ramp: no second section, no top, down again.
  const LoadResult plain = load(kMinimalYaml +
                                "terrain: [{type: ramp, x: 2, y: 5, length_m: 2, width_m: 1, "
                                "angle_deg: 5}]\n");
  ASSERT_TRUE(plain.ok) << plain.error;
  EXPECT_TRUE(plain.scenario.terrain[0].descend);
  EXPECT_EQ(plain.scenario.terrain[0].length2_m, 0.0);
  EXPECT_EQ(plain.scenario.terrain[0].footprint_length_m(), 4.0);
}

TEST(ScenarioTerrain, RampErrors) {
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "length2_m: 1, ", ""),
                         {"test_scn.yaml:11: terrain[0].length2_m: missing required key "
                          "(angle2_deg is given)"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "angle2_deg: 11, ", ""),
                         {"terrain[0].angle2_deg: missing required key (length2_m is given)"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "angle2_deg: 11", "angle2_deg: 31"),
                         {"terrain[0].angle2_deg: expected a number in [0.5, 30], got 31"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "length2_m: 1", "length2_m: 0"),
                         {"terrain[0].length2_m: expected a number in [0.01, 100], got 0"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "top_m: 0.5", "top_m: -1"),
                         {"terrain[0].top_m: expected a number in [0, 100], got -1"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "descend: false", "descend: no"),
                         {"terrain[0].descend: expected true or false, got \"no\""}));
}

TEST(ScenarioTerrain, StepTrenchAndObstacleErrors) {
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "height_m: -0.2", "height_m: -0.6"),
                         {"test_scn.yaml:12: terrain[1].height_m: expected a number in [-0.5, "
                          "0.5], got -0.6"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "height_m: -0.2", "height_m: 0.001"),
                         {"terrain[1].height_m: expected a number in [-0.5, -0.005] or [0.005, "
                          "0.5] (a raised platform or a pit), got 0.001"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "depth_m: 0.3", "depth_m: 0"),
                         {"terrain[2].depth_m: expected a number in [0.005, 1], got 0"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, ", depth_m: 0.3", ""),
                         {"terrain[2].depth_m: missing required key"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "depth_m: 0.3", "height_m: 0.3"),
                         {"terrain[2].height_m: unknown key (allowed: type, x, y, yaw_deg, "
                          "length_m, width_m, depth_m)"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "type: trench", "type: hole"),
                         {"terrain[2].type: expected one of ramp, step, trench, got \"hole\""}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "height_m: 0.5", "height_m: 0"),
                         {"obstacles[0].height_m: expected a number in [0.01, 10], got 0"}));
  EXPECT_TRUE(fails_with(edit(kTerrainYaml, "radius_m: 0.3}", "radius_m: 0.3, height_m: 11}"),
                         {"obstacles[1].height_m: expected a number in [0.01, 10], got 11"}));
}

TEST(ScenarioTerrain, RobotTerrainLimitsOverride) {
  const std::string base =
      edit(kMinimalYaml, "robot: {preset: pioneer3at}",
           "robot: {preset: pioneer3at, terrain_limits: {max_step_up_m: 0.2}}");
  const LoadResult r = load(base);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.robot.terrain_limits.max_step_up_m, 0.2);
  EXPECT_EQ(r.scenario.robot.terrain_limits.max_slope_deg, 19.0);  // the preset's
  EXPECT_EQ(r.scenario.robot.terrain_limits.max_step_down_m, 0.15);
  EXPECT_TRUE(fails_with(edit(base, "max_step_up_m: 0.2", "max_step_up_m: 2"),
                         {"robot.terrain_limits.max_step_up_m: expected a number in [0.005, 1], "
                          "got 2"}));
  EXPECT_TRUE(fails_with(edit(base, "max_step_up_m: 0.2", "max_slope_deg: 0"),
                         {"robot.terrain_limits.max_slope_deg: expected a number in [1, 60], "
                          "got 0"}));
  EXPECT_TRUE(fails_with(edit(base, "max_step_up_m: 0.2", "max_step_down_m: 3"),
                         {"robot.terrain_limits.max_step_down_m: expected a number in [0.005, 2], "
                          "got 3"}));
  EXPECT_TRUE(fails_with(edit(base, "max_step_up_m: 0.2", "max_step: 0.1"),
                         {"robot.terrain_limits.max_step: unknown key (allowed: max_slope_deg, "
                          "max_step_up_m, max_step_down_m)"}));
}

}  // namespace
}  // namespace carril::sim
