// Rejections: each kind of error gives one message "<file>:<line>: <key path>: ...".
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "host_sim/scenario/ScenarioLoader.hpp"
#include "tests/unit/scenario/ScenarioTestUtil.hpp"

namespace carril::sim {
namespace {

using test::edit;
using test::fails_with;
using test::kFullYaml;
using test::kMinimalYaml;
using test::kPath;
using test::line_of;

const std::string kLine2 =
    "{color: white, width_m: 0.06, points: [[6, 4], [0, 4]]}";  // lines[2] in kFullYaml

std::string at_line(const std::string& text, const std::string& needle) {
  return kPath + ":" + std::to_string(line_of(text, needle)) + ": ";
}

TEST(ScenarioErrors, OutOfRangeNamesPathLineAndValue) {
  const std::string yaml = edit(kFullYaml, "width_m: 0.06", "width_m: -1");
  const LoadResult r = test::load(yaml);
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error, at_line(yaml, "width_m: -1") +
                         "lines[2].width_m: expected a number in [0.005, 0.5], got -1");
}

TEST(ScenarioErrors, MissingRequiredKey) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "  strategy: line_priority\n", ""),
                         {"mission.strategy", "missing required key"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240\n", ""), {"duration_s", "missing"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "{x: 1.0, y: -2.0, yaw_deg: 90}", "{x: 1.0, y: -2.0}"),
                         {"robot.start.yaw_deg", "missing"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "yaw_deg: 30, size_m: [1.0, 2.0]", "yaw_deg: 30"),
                         {"obstacles[0].size_m", "missing"}));
}

TEST(ScenarioErrors, UnknownKeyNestedListsAllowedKeys) {
  const std::string yaml =
      edit(kFullYaml, "{color: white, width_m: 0.05", "{colour: white, width_m: 0.05");
  EXPECT_TRUE(fails_with(yaml, {at_line(yaml, "colour") + "lines[0].colour: unknown key (allowed: "
                                                          "color, width_m, points, arc)"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "  camera: {noise_std", "  camerra: {noise_std"),
                         {"robot.camerra: unknown key (allowed: preset, start, camera, lidar, "
                          "limits, terrain_limits)"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "seed: 7", "sed: 7"), {"sed: unknown key"}));
}

TEST(ScenarioErrors, UnknownOverrideKeyIsNotInThePresetSchema) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "camera: {noise_std: 4.0}", "camera: {fov: 70}"),
                         {"robot.camera.fov: unknown key"}));
}

TEST(ScenarioErrors, OverrideRangeChecks) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "noise_std: 4.0", "noise_std: -4"),
                         {"robot.camera.noise_std: expected a number in [0, 100], got -4"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "lidar: {beams: 271}", "lidar: {beams: 4096}"),
                         {"robot.lidar.beams: expected an integer in [2, 2048], got 4096"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "lidar: {beams: 271}", "lidar: {range_min_m: 25}"),
                         {"robot.lidar.range_min_m: expected a number in [0, 10], got 25"}));
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "lidar: {beams: 271}", "lidar: {range_max_m: 5, range_min_m: 8}"),
                 {"robot.lidar.range_min_m", "range_max_m = 5", "got 8"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "lidar: {beams: 271}", "lidar: {range_max_m: 0.01}"),
                         {"robot.lidar.range_max_m", "got 0.01"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "camera: {noise_std: 4.0}", "camera: {width: 2000}"),
                         {"robot.camera.width: expected an integer in [32, 1280], got 2000"}));
}

TEST(ScenarioErrors, WrongType) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "width_m: 0.04", "width_m: \"wide\""),
                         {"lines[1].width_m: expected a number, got \"wide\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240", "duration_s: long"),
                         {"duration_s: expected a number, got \"long\""}));
  EXPECT_TRUE(
      fails_with(edit(kMinimalYaml, "lines:\n  - {color: white, points: [[0, 0], [1, 0]]}\n",
                      "lines: {a: 1}\n"),
                 {"lines: expected a list, got a map"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "end_reached: true", "end_reached: yes"),
                         {"expect.end_reached: expected true or false, got \"yes\""}));
  // A quoted number is a string in YAML.
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240", "duration_s: \"240\""),
                         {"duration_s: expected a number, got \"240\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240", "duration_s:"),
                         {"duration_s: expected a number, got null"}));
}

TEST(ScenarioErrors, NumbersMustBeFinite) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240", "duration_s: .inf"),
                         {"duration_s: expected a finite number, got .inf"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "x: 6, y: 2", "x: .nan, y: 2"),
                         {"obstacles[1].x: expected a finite number"}));
  // Overflowing text must not raise a floating-point exception (traps are on in tests).
  EXPECT_TRUE(fails_with(edit(kFullYaml, "x: 6, y: 2", "x: 1e400, y: 2"),
                         {"obstacles[1].x: expected a finite number, got 1e400"}));
}

TEST(ScenarioErrors, OutOfRange) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "duration_s: 240", "duration_s: 0"),
                         {"duration_s: expected a number in [0.1, 86400], got 0"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "min_progress: 1.0", "min_progress: 1.5"),
                         {"expect.min_progress: expected a number in [0, 1], got 1.5"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "angle_deg: 5", "angle_deg: 45"),
                         {"terrain[0].angle_deg: expected a number in [0.5, 30], got 45"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "size_m: [1.0, 2.0]", "size_m: [1.0, 0]"),
                         {"obstacles[0].size_m[1]: expected a number in [0.01, 100], got 0"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "speed_mps: 0.8", "speed_mps: 1.3"),
                         {"mission.speed_mps", "max_speed_mps = 1.2", "got 1.3"}));
}

TEST(ScenarioErrors, NonIntegerWhereIntegerExpected) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "seed: 7", "seed: 1.5"),
                         {"seed: expected an integer >= 0, got 1.5"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "seed: 7", "seed: -1"), {"seed", "got -1"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "max_collisions: 0", "max_collisions: 2.0"),
                         {"expect.max_collisions", "integer", "got 2.0"}));
}

TEST(ScenarioErrors, UnknownColourName) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "line_color: white", "line_color: purple"),
                         {"mission.line_color: expected a colour name", "got \"purple\""}));
}

TEST(ScenarioErrors, RgbComponentOutOfRange) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "[255, 0, 0]", "[255, 256, 0]"),
                         {"lines[1].color[1]: expected an integer in [0, 255], got 256"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "[90, 91, 92]", "[90, 91]"),
                         {"floor.color: expected", "got a list of 2"}));
}

TEST(ScenarioErrors, UnknownStrategy) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "strategy: line_priority", "strategy: fastest"),
                         {"mission.strategy: expected one of line_priority, marks, pid, got "
                          "\"fastest\""}));
}

TEST(ScenarioErrors, UnsupportedMissionType) {
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "type: follow_line", "type: mowing"),
                 {"mission.type", "expected one of follow_line, goto, waypoints, coverage"}));
  // A mission type's own keys: follow_line's strategy in a coverage mission is named.
  EXPECT_TRUE(fails_with(edit(kFullYaml, "type: follow_line", "type: coverage"),
                         {"mission.strategy", "unknown key"}));
}

TEST(ScenarioErrors, LinePriorityNeedsMecanum) {
  const std::string yaml = edit(edit(kFullYaml, "preset: campero", "preset: pioneer3at"),
                                "max_speed_mps: 1.2", "max_speed_mps: 0.9");
  EXPECT_TRUE(fails_with(yaml, {"mission.strategy", "pioneer3at", "mecanum"}));
}

TEST(ScenarioErrors, UnknownPreset) {
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "preset: campero", "preset: roomba"),
                 {"robot.preset: expected one of campero, create3, pioneer3at, got \"roomba\""}));
}

TEST(ScenarioErrors, BrokenPresetFileIsNamed) {
  // A robots dir whose campero.yaml has a bad camera width.
  const auto dir = std::filesystem::path(::testing::TempDir()) / "carril_bad_robots";
  std::filesystem::create_directories(dir);
  std::string preset;
  {
    std::ifstream in(test::robots_dir() + "/campero.yaml");
    preset.assign(std::istreambuf_iterator<char>(in), {});
  }
  {
    std::ofstream out(dir / "campero.yaml");
    out << edit(preset, "width: 640", "width: 6400");
  }
  const LoadResult r = load_scenario_text(kFullYaml, kPath, dir.string());
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error.rfind(kPath + ":", 0), 0U) << r.error;
  EXPECT_NE(r.error.find((dir / "campero.yaml").string()), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("camera.width: expected an integer in [32, 1280], got 6400"),
            std::string::npos)
      << r.error;

  RobotSpec spec;
  spec.mass_kg = 1.0;
  std::string error;
  EXPECT_FALSE(load_robot_preset((dir / "campero.yaml").string(), spec, error));
  EXPECT_EQ(error.rfind((dir / "campero.yaml").string() + ":", 0), 0U) << error;
  EXPECT_DOUBLE_EQ(spec.mass_kg, 1.0);  // untouched on failure
  EXPECT_FALSE(load_robot_preset((dir / "missing.yaml").string(), spec, error));
  EXPECT_EQ(error, (dir / "missing.yaml").string() + ": cannot open");
}

TEST(ScenarioErrors, PresetWithoutALidarIsRejected) {
  // The simulator always simulates the lidar: a robot file saying it has none cannot be run.
  const auto dir = std::filesystem::path(::testing::TempDir()) / "carril_no_lidar_robots";
  std::filesystem::create_directories(dir);
  std::string preset;
  {
    std::ifstream in(test::robots_dir() + "/campero.yaml");
    preset.assign(std::istreambuf_iterator<char>(in), {});
  }
  {
    std::ofstream out(dir / "campero.yaml");
    out << edit(preset, "lidar: {x_m", "lidar: {present: false, x_m");
  }
  const LoadResult r = load_scenario_text(kFullYaml, kPath, dir.string());
  EXPECT_TRUE(fails_with(r, {at_line(kFullYaml, "preset: campero") +
                             "robot.preset: expected a robot with a lidar (the simulator always "
                             "simulates one; " +
                             (dir / "campero.yaml").string() + " says lidar.present: false)"}));
  // A scenario cannot switch it off either: present is not an override key.
  EXPECT_TRUE(fails_with(edit(kFullYaml, "lidar: {beams: 271}", "lidar: {present: false}"),
                         {"robot.lidar.present: unknown key"}));
}

TEST(ScenarioErrors, YamlSyntaxErrorNamesFileAndLine) {
  const std::string yaml = edit(kFullYaml, "seed: 7", "seed: [7, 8");
  const LoadResult r = test::load(yaml);
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error.rfind(kPath + ":", 0), 0U) << r.error;
  EXPECT_NE(r.error.find("invalid YAML"), std::string::npos) << r.error;
  // yaml-cpp reports where it noticed; it must be a real line number at or after the bad one.
  const int bad = line_of(yaml, "seed: [7, 8");
  const auto colon = r.error.find(':', kPath.size() + 1);
  const int reported = std::stoi(r.error.substr(kPath.size() + 1, colon - kPath.size() - 1));
  EXPECT_GE(reported, bad) << r.error;

  EXPECT_TRUE(fails_with("name: a\n  bad: [indent\n", {"invalid YAML"}));
}

// Issue 46 item 2: movers are checked as obstacles are, with their path and speed.
TEST(ScenarioErrors, BadMoversAreNamed) {
  const std::string person =
      "movers:\n  - {shape: cylinder, radius_m: 0.25, path: [[0, 2], [0, -2]], "
      "speed_mps: 1.6}\n";
  EXPECT_TRUE(fails_with(kMinimalYaml + "movers:\n  - {shape: cylinder, radius_m: 0.25, path: [[0, "
                                        "2], [0, -2]], speed_mps: 9}\n",
                         {"movers[0].speed_mps: expected a number in [0.05, 5], got 9"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "movers:\n  - {shape: cylinder, radius_m: 0.25, path: [[0, "
                                        "2]], speed_mps: 1}\n",
                         {"movers[0].path"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "movers:\n  - {shape: box, radius_m: 0.25, path: [[0, 2], "
                                        "[0, -2]], speed_mps: 1}\n",
                         {"movers[0].radius_m: unknown key"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + person + "  - {shape: disc}\n", {"movers[1].shape"}));
}

TEST(ScenarioErrors, EmptyOrMultiDocumentFile) {
  EXPECT_TRUE(fails_with("", {"expected a map, got an empty file"}));
  EXPECT_TRUE(fails_with("# only a comment\n", {"empty file"}));
  EXPECT_TRUE(fails_with("- 1\n- 2\n", {"(top level): expected a map, got a list"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "---\nname: b\n", {"one YAML document"}));
}

TEST(ScenarioErrors, DuplicateKey) {
  EXPECT_TRUE(
      fails_with(kMinimalYaml + "name: again\n", {"name: duplicate key (first at line 1)"}));
}

TEST(ScenarioErrors, MissingFile) {
  const std::string path = "/nonexistent/dir/scn.yaml";
  const LoadResult r = load_scenario(path, test::robots_dir());
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error, path + ": cannot open");
}

TEST(ScenarioErrors, PointsAndArcBothOrNeither) {
  EXPECT_TRUE(fails_with(
      edit(kFullYaml, "width_m: 0.04, arc:", "width_m: 0.04, points: [[0, 0], [1, 0]], arc:"),
      {"lines[1]: expected exactly one of points or arc, got both"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, kLine2, "{color: white}"),
                         {"lines[2]: expected exactly one of points or arc, got neither"}));
}

TEST(ScenarioErrors, BadPoints) {
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "[[6, 4], [0, 4]]", "[[6, 4]]"),
                 {"lines[2].points: expected a list of at least 2 items, got a list of 1"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "[[6, 4], [0, 4]]", "[[6, 4], [0, 4, 1]]"),
                         {"lines[2].points[1]: expected [x, y] (2 numbers), got a list of 3"}));
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "start_deg: -90, end_deg: 270", "start_deg: 10, end_deg: 10"),
                 {"lines[1].arc.end_deg", "got 10"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "radius_m: 3.0", "radius_m: 0"),
                         {"lines[1].arc.radius_m: expected a number in [0.05, 100], got 0"}));
}

TEST(ScenarioErrors, ShapeSpecificKeys) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "size_m: [1.0, 2.0]", "size_m: [1.0, 2.0], radius_m: 1"),
                         {"obstacles[0].radius_m: unknown key (allowed: shape, x, y, yaw_deg, "
                          "size_m, height_m)"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "{shape: cylinder", "{shape: cone"),
                         {"obstacles[1].shape: expected one of box, cylinder, got \"cone\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "height_m: 0.2", "angle_deg: 3"),
                         {"terrain[1].angle_deg: unknown key"}));
}

TEST(ScenarioErrors, NoLineOfTheMissionColour) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "line_color: white", "line_color: green"),
                         {"lines: expected at least one line of mission.line_color green"}));
  const LoadResult r = test::load(kMinimalYaml.substr(0, kMinimalYaml.find("lines:")));
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error, kPath +
                         ": lines: expected at least one line of mission.line_color white, "
                         "got no lines");
}

TEST(ScenarioErrors, BadName) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "name: corners-1_b", "name: ../up"),
                         {"name: expected a name of", "got \"../up\""}));
}

TEST(ScenarioErrors, LimitOverrideBelowCruiseNeedsExplicitSpeed) {
  const std::string yaml =
      edit(edit(kFullYaml, "max_speed_mps: 1.2", "max_speed_mps: 0.3"), "  speed_mps: 0.8\n", "");
  EXPECT_TRUE(fails_with(yaml, {"mission.speed_mps", "cruise_speed_mps 0.5"}));
}

}  // namespace
}  // namespace carril::sim
