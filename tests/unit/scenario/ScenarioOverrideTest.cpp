// Robot preset and strategy overrides (carril_sim --preset / --strategy): applied to the YAML
// before validation, so every rule of the file format holds for them too.
#include <gtest/gtest.h>

#include <string>

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
using test::robots_dir;

LoadResult load_with(const std::string& yaml, const std::string& preset,
                     const std::string& strategy) {
  return load_scenario_text(yaml, kPath, robots_dir(), ScenarioOverrides{preset, strategy});
}

TEST(ScenarioOverride, EmptyOverridesKeepTheFile) {
  const LoadResult plain = test::load(kFullYaml);
  const LoadResult with = load_with(kFullYaml, "", "");
  ASSERT_TRUE(plain.ok) << plain.error;
  ASSERT_TRUE(with.ok) << with.error;
  EXPECT_TRUE(ScenarioOverrides{}.empty());
  EXPECT_FALSE((ScenarioOverrides{"campero", ""}.empty()));
  EXPECT_FALSE((ScenarioOverrides{"", "pid"}.empty()));
  EXPECT_EQ(with.scenario.robot.preset, "campero");
  EXPECT_EQ(with.scenario.mission.strategy, "line_priority");
}

TEST(ScenarioOverride, PresetAndStrategyReplaceTheFilesValues) {
  const LoadResult r = load_with(kFullYaml, "pioneer3at", "pid");
  ASSERT_TRUE(r.ok) << r.error;
  const Scenario& s = r.scenario;
  EXPECT_EQ(s.robot.preset, "pioneer3at");
  EXPECT_EQ(s.robot.drive, DriveType::Differential);
  // The new preset's own values...
  EXPECT_DOUBLE_EQ(s.robot.length_m, 0.508);
  EXPECT_EQ(s.robot.lidar.fov_deg, 180.0);
  // ...with the file's robot overrides merged onto it, as for a file naming that preset.
  EXPECT_DOUBLE_EQ(s.robot.camera.noise_std, 4.0);
  EXPECT_EQ(s.robot.lidar.beams, 271);
  EXPECT_DOUBLE_EQ(s.robot.limits.max_speed_mps, 1.2);
  EXPECT_EQ(s.mission.strategy, "pid");
  // Everything else is the file's.
  EXPECT_EQ(s.name, "corners-1_b");
  EXPECT_DOUBLE_EQ(s.robot.start.x, 1.0);
  EXPECT_DOUBLE_EQ(s.mission.speed_mps, 0.8);
  EXPECT_EQ(s.lines.size(), 3U);
}

TEST(ScenarioOverride, SameResultAsEditingTheFile) {
  const LoadResult over = load_with(kMinimalYaml, "campero", "line_priority");
  const LoadResult edited =
      test::load(edit(edit(kMinimalYaml, "preset: pioneer3at", "preset: campero"), "strategy: pid",
                      "strategy: line_priority"));
  ASSERT_TRUE(over.ok) << over.error;
  ASSERT_TRUE(edited.ok) << edited.error;
  EXPECT_EQ(over.scenario.robot.preset, edited.scenario.robot.preset);
  EXPECT_EQ(over.scenario.robot.drive, DriveType::Mecanum);
  EXPECT_EQ(over.scenario.mission.strategy, edited.scenario.mission.strategy);
  // The speed default comes from the overriding preset's cruise speed.
  EXPECT_DOUBLE_EQ(over.scenario.mission.speed_mps, edited.scenario.mission.speed_mps);
  EXPECT_DOUBLE_EQ(over.scenario.robot.limits.max_speed_mps,
                   edited.scenario.robot.limits.max_speed_mps);
}

TEST(ScenarioOverride, OnlyOneOfThem) {
  const LoadResult p = load_with(kMinimalYaml, "campero", "");
  ASSERT_TRUE(p.ok) << p.error;
  EXPECT_EQ(p.scenario.robot.preset, "campero");
  EXPECT_EQ(p.scenario.mission.strategy, "pid");
  const LoadResult s = load_with(kFullYaml, "", "marks");
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(s.scenario.robot.preset, "campero");
  EXPECT_EQ(s.scenario.mission.strategy, "marks");
}

TEST(ScenarioOverride, LinePriorityOnADifferentialPresetIsStillRejected) {
  // The file's line_priority with an overriding differential preset...
  const LoadResult a = load_with(kFullYaml, "pioneer3at", "");
  EXPECT_TRUE(fails_with(a, {"mission.strategy", "line_priority needs a mecanum drive",
                             "preset pioneer3at is differential", "got \"line_priority\"",
                             "(overridden: robot.preset = pioneer3at)"}));
  // ...reported at the strategy's line in the file.
  EXPECT_TRUE(fails_with(
      a, {kPath + ":" + std::to_string(line_of(kFullYaml, "strategy: line_priority")) + ":"}));
  // An overriding line_priority on the file's differential preset, and both overridden.
  EXPECT_TRUE(fails_with(load_with(kMinimalYaml, "", "line_priority"),
                         {"mission.strategy", "line_priority needs a mecanum drive",
                          "(overridden: mission.strategy = line_priority)"}));
  EXPECT_TRUE(fails_with(load_with(kFullYaml, "pioneer3at", "line_priority"),
                         {"mission.strategy", "preset pioneer3at is differential",
                          "(overridden: robot.preset = pioneer3at, mission.strategy = "
                          "line_priority)"}));
}

TEST(ScenarioOverride, UnknownNamesAreStillRejected) {
  EXPECT_TRUE(fails_with(load_with(kFullYaml, "robotnik", ""),
                         {"robot.preset", "campero", "pioneer3at", "got \"robotnik\""}));
  EXPECT_TRUE(fails_with(load_with(kFullYaml, "", "fastest"),
                         {"mission.strategy", "line_priority", "marks", "pid", "got \"fastest\""}));
  // A preset name that is allowed but whose file is missing: the preset loader's error.
  const LoadResult r = load_scenario_text(kFullYaml, kPath, "/nonexistent/robots",
                                          ScenarioOverrides{"pioneer3at", "pid"});
  EXPECT_TRUE(fails_with(r, {"robot.preset", "cannot load robot preset", "pioneer3at.yaml"}));
}

TEST(ScenarioOverride, OtherErrorsOfTheFileStillReported) {
  const std::string bad = edit(kFullYaml, "duration_s: 240", "duration_s: -1");
  EXPECT_TRUE(
      fails_with(load_with(bad, "pioneer3at", "pid"), {"duration_s", "got -1", "(overridden: "}));
}

TEST(ScenarioOverride, AddsAKeyTheFileLacks) {
  const std::string no_strategy =
      edit(kMinimalYaml, "mission: {type: follow_line, strategy: pid, line_color: white}",
           "mission: {type: follow_line, line_color: white}");
  EXPECT_TRUE(test::fails_with(no_strategy, {"mission.strategy", "missing required key"}));
  const LoadResult r = load_with(no_strategy, "", "marks");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.mission.strategy, "marks");
}

TEST(ScenarioOverride, DoesNotCreateOrRepairASection) {
  // No robot section: still a missing required key, not a robot made of the override.
  const std::string no_robot = edit(kMinimalYaml, "robot: {preset: pioneer3at}\n", "");
  EXPECT_TRUE(fails_with(load_with(no_robot, "campero", ""), {"robot", "missing required key"}));
  // A section that is not a map is still a type error.
  const std::string scalar_mission =
      edit(kMinimalYaml, "mission: {type: follow_line, strategy: pid, line_color: white}",
           "mission: follow_line");
  EXPECT_TRUE(fails_with(load_with(scalar_mission, "", "pid"), {"mission", "expected a map"}));
  // A document that is not a map at all.
  EXPECT_TRUE(fails_with(load_with("- 1\n- 2\n", "campero", "marks"), {"(top level)"}));
}

TEST(ScenarioOverride, FileLoaderPassesThemOn) {
  const std::string path = CARRIL_SOURCE_DIR "/scenarios/circle.yaml";
  const LoadResult r = load_scenario(path, robots_dir(), ScenarioOverrides{"pioneer3at", "pid"});
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.robot.preset, "pioneer3at");
  EXPECT_EQ(r.scenario.mission.strategy, "pid");
  const LoadResult bad =
      load_scenario(path, robots_dir(), ScenarioOverrides{"pioneer3at", "line_priority"});
  ASSERT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("circle.yaml:"), std::string::npos) << bad.error;
  EXPECT_NE(bad.error.find("line_priority needs a mecanum drive"), std::string::npos) << bad.error;
}

// The experiment matrix (tests/scenario/CMakeLists.txt, tools/experiments.sh): every scenario
// loads with each of its four robot/strategy combinations.
TEST(ScenarioOverride, ExperimentMatrixLoads) {
  const char* scenarios[] = {"circle", "corners", "smooth", "corners_red", "smooth_red"};
  const ScenarioOverrides combos[] = {{"campero", "marks"},
                                      {"campero", "line_priority"},
                                      {"pioneer3at", "marks"},
                                      {"pioneer3at", "pid"}};
  for (const char* name : scenarios) {
    const std::string path = std::string(CARRIL_SOURCE_DIR "/scenarios/") + name + ".yaml";
    for (const ScenarioOverrides& o : combos) {
      const LoadResult r = load_scenario(path, robots_dir(), o);
      ASSERT_TRUE(r.ok) << name << " " << o.preset << " " << o.strategy << ": " << r.error;
      EXPECT_EQ(r.scenario.name, name);
      EXPECT_EQ(r.scenario.robot.preset, o.preset);
      EXPECT_EQ(r.scenario.mission.strategy, o.strategy);
      EXPECT_DOUBLE_EQ(r.scenario.mission.speed_mps, 0.5);
    }
    EXPECT_FALSE(load_scenario(path, robots_dir(), {"pioneer3at", "line_priority"}).ok) << name;
  }
}

}  // namespace
}  // namespace carril::sim
