// Rules added by issue 7: explicit YAML tags, the end-stop expectation, physical ranges and
// derived quantities, size limits, zero-length tape, the start footprint and tape colours.
#include <gtest/gtest.h>

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

std::string at_line(const std::string& text, const std::string& needle) {
  return kPath + ":" + std::to_string(line_of(text, needle)) + ": ";
}

// ---- Explicit tags ----

TEST(ScenarioRules, TaggedNumberIsNotANumber) {
  for (const char* tag : {"!!str", "!!int", "!!float", "!foo"}) {
    const std::string yaml =
        edit(kFullYaml, "duration_s: 240", std::string("duration_s: ") + tag + " 240");
    const LoadResult r = test::load(yaml);
    ASSERT_FALSE(r.ok) << tag;
    EXPECT_EQ(r.error, at_line(yaml, "duration_s:") + "duration_s: expected a number, got " + tag +
                           " \"240\"");
  }
}

TEST(ScenarioRules, TaggedIntegerAndBooleanRejected) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "seed: 7", "seed: !!int 7"),
                         {"seed: expected a number, got !!int \"7\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "end_reached: true", "end_reached: !!bool true"),
                         {"expect.end_reached: expected true or false, got !!bool \"true\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "end_reached: true", "end_reached: !!str true"),
                         {"expect.end_reached: expected true or false, got !!str \"true\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "[90, 91, 92]", "[90, !!int 91, 92]"),
                         {"floor.color[1]: expected a number, got !!int \"91\""}));
}

TEST(ScenarioRules, AnyExplicitTagRejected) {
  EXPECT_TRUE(fails_with(edit(kFullYaml, "name: corners-1_b", "name: !!str corners-1_b"),
                         {"name: expected a string, got !!str \"corners-1_b\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "strategy: line_priority", "strategy: !s line_priority"),
                         {"mission.strategy: expected a string, got !s \"line_priority\""}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "floor: {color", "floor: !!map {color"),
                         {"floor: expected a map, got !!map a map"}));
  EXPECT_TRUE(
      fails_with(edit(kFullYaml, "[[0, 0], [6, 0], [6, 4]]", "!!seq [[0, 0], [6, 0], [6, 4]]"),
                 {"lines[0].points: expected a list, got !!seq a list"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "seed: 7", "!!str seed: 7"),
                         {"expected a string key, got !!str \"seed\""}));
}

TEST(ScenarioRules, QuotedStringsStillAccepted) {
  const LoadResult r = test::load(edit(kFullYaml, "name: corners-1_b", "name: 'corners-1_b'"));
  EXPECT_TRUE(r.ok) << r.error;
}

// ---- expect.max_end_stop_error_m ----

TEST(ScenarioRules, MaxEndStopError) {
  const LoadResult r = test::load(
      edit(kFullYaml, "  min_laps: 1\n", "  min_laps: 1\n  max_end_stop_error_m: 0.1\n"));
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_TRUE(r.scenario.expect.max_end_stop_error_m.has_value());
  EXPECT_DOUBLE_EQ(*r.scenario.expect.max_end_stop_error_m, 0.1);
  const LoadResult only = test::load(kMinimalYaml + "expect: {max_end_stop_error_m: 0.2}\n");
  ASSERT_TRUE(only.ok) << only.error;
  EXPECT_TRUE(only.scenario.expect.any());
  EXPECT_FALSE(test::load(kMinimalYaml).scenario.expect.max_end_stop_error_m.has_value());
  EXPECT_TRUE(fails_with(kMinimalYaml + "expect: {max_end_stop_error_m: 0}\n",
                         {"expect.max_end_stop_error_m: expected a number > 0, got 0"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "expect: {max_end_stop_error_m: -1}\n",
                         {"expect.max_end_stop_error_m: expected a number > 0, got -1"}));
}

}  // namespace
}  // namespace carril::sim
