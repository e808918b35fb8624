// The scenario keys campaigns perturb: tape_wear, glare, robot.camera.exposure and
// robot.lidar.dropout load with their defaults and values; a bad value is one error naming the
// key and its range.
#include <gtest/gtest.h>

#include <string>

#include "host_sim/scenario/ColorCheck.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim {
namespace {

const std::string kRobots = std::string(CARRIL_SOURCE_DIR) + "/config/robots";
const std::string kBase = R"(name: p
duration_s: 1
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[0, 0], [5, 0]]}]
)";

LoadResult load(const std::string& extra, const std::string& robot = "robot: {preset: campero}\n") {
  return load_scenario_text(kBase + robot + extra, "p.yaml", kRobots);
}

TEST(ScenarioPerturbationsTest, DefaultsChangeNothing) {
  const LoadResult r = load("");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_FALSE(r.scenario.tape_wear.any());
  EXPECT_EQ(r.scenario.glare.intensity, 0.0);
  EXPECT_EQ(r.scenario.robot.camera.exposure, 1.0);
  EXPECT_EQ(r.scenario.robot.lidar.dropout, 0.0);
  EXPECT_EQ(r.scenario.floor_speckle, 0.15);
}

TEST(ScenarioPerturbationsTest, TheFloorSpeckleKeepsTheDefaultShadesAndScales) {
  // The default's shades are the ones scenarios were always rendered with.
  EXPECT_EQ(speckle_shade(0.15, 0.0), 0.85);
  EXPECT_EQ(speckle_shade(0.15, 0.25), 0.85 + 0.2 * 0.25);
  EXPECT_EQ(speckle_shade(0.15, 0.75), 1.05 + 0.2 * 0.25);
  // Another speckle: [1 - s, 1 - s/3) and [1 + s/3, 1 + s).
  EXPECT_DOUBLE_EQ(speckle_shade(0.3, 0.0), 0.7);
  EXPECT_NEAR(speckle_shade(0.3, 0.4999999), 0.9, 1e-6);
  EXPECT_DOUBLE_EQ(speckle_shade(0.3, 0.5), 1.1);
  EXPECT_NEAR(speckle_shade(0.3, 0.9999999), 1.3, 1e-6);
  EXPECT_DOUBLE_EQ(speckle_shade(0.0, 0.2), 1.0);
  const LoadResult r = load("floor: {color: [90, 90, 90], speckle: 0.25}\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_DOUBLE_EQ(r.scenario.floor_speckle, 0.25);
}

TEST(ScenarioPerturbationsTest, TheColourCheckHoldsForTheSpeckleGiven) {
  // White tape is seen at a value of 170 and more. A floor of (140, 140, 140) is told from it at
  // the default speckle (its lightest shade x1.15 = 161), not at 0.3 (x1.3 = 182).
  const LoadResult ok = load("floor: {color: [140, 140, 140]}\n");
  EXPECT_TRUE(ok.ok) << ok.error;
  const LoadResult r = load("floor: {color: [140, 140, 140], speckle: 0.3}\n");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("x1.3"), std::string::npos) << r.error;
}

TEST(ScenarioPerturbationsTest, TheKeysLoad) {
  const LoadResult r = load(
      "tape_wear: {gaps_per_m: 0.2, gap_length_m: 0.15, fade: 0.3}\n"
      "glare: {intensity: 90, radius_px: 40, period_s: 5}\n",
      "robot: {preset: campero, camera: {exposure: 1.6}, lidar: {dropout: 0.1}}\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_DOUBLE_EQ(r.scenario.tape_wear.gaps_per_m, 0.2);
  EXPECT_DOUBLE_EQ(r.scenario.tape_wear.gap_length_m, 0.15);
  EXPECT_DOUBLE_EQ(r.scenario.tape_wear.fade, 0.3);
  EXPECT_DOUBLE_EQ(r.scenario.glare.intensity, 90.0);
  EXPECT_DOUBLE_EQ(r.scenario.glare.radius_px, 40.0);
  EXPECT_DOUBLE_EQ(r.scenario.glare.period_s, 5.0);
  EXPECT_DOUBLE_EQ(r.scenario.robot.camera.exposure, 1.6);
  EXPECT_DOUBLE_EQ(r.scenario.robot.lidar.dropout, 0.1);
}

void expect_error(const LoadResult& r, const std::string& key, const std::string& range) {
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("p.yaml"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find(key), std::string::npos) << r.error;
  EXPECT_NE(r.error.find(range), std::string::npos) << r.error;
}

TEST(ScenarioPerturbationsTest, BadValuesNameTheKey) {
  expect_error(load("tape_wear: {gaps_per_m: 6}\n"), "tape_wear.gaps_per_m", "[0, 5]");
  expect_error(load("floor: {color: [90, 90, 90], speckle: 0.4}\n"), "floor.speckle", "[0, 0.3]");
  expect_error(load("tape_wear: {gap_length_m: 0}\n"), "tape_wear.gap_length_m", "[0.005, 2]");
  expect_error(load("tape_wear: {fade: 1.5}\n"), "tape_wear.fade", "[0, 1]");
  expect_error(load("tape_wear: {gaps: 3}\n"), "tape_wear.gaps", "");
  expect_error(load("glare: {radius_px: 40}\n"), "glare.intensity", "");
  expect_error(load("glare: {intensity: 300}\n"), "glare.intensity", "[0, 255]");
  expect_error(load("", "robot: {preset: campero, camera: {exposure: 5}}\n"),
               "robot.camera.exposure", "[0.25, 4]");
  expect_error(load("", "robot: {preset: campero, lidar: {dropout: 0.95}}\n"),
               "robot.lidar.dropout", "[0, 0.9]");
}

}  // namespace
}  // namespace carril::sim
