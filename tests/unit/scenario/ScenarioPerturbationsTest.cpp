// The scenario keys campaigns perturb: tape_wear, glare, robot.camera.exposure and
// robot.lidar.dropout load with their defaults and values; a bad value is one error naming the
// key and its range.
#include <gtest/gtest.h>

#include <string>

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
