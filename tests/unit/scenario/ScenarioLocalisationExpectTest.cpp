// expect's localisation keys: max_time_to_converge_s, max_relocalise_s and
// max_localisation_rmse_m are read on a map; without one (or max_relocalise_s without a kidnap,
// or out of range) the error names the file and the key.
#include <gtest/gtest.h>

#include <string>

#include "tests/unit/scenario/ScenarioTestUtil.hpp"

namespace carril::sim {
namespace {

const std::string kOnMap = R"(name: on_map
duration_s: 10
map: maps/house.yaml
robot: {preset: pioneer3at}
mission: {type: goto, goal: {x: 3.6, y: 1.4, yaw_deg: 90}}
)";
const std::string kKidnap = "localisation:\n  kidnap:\n    - {t_s: 5, x: 0, y: 0, yaw_deg: 0}\n";
const std::string kPath = std::string(CARRIL_SOURCE_DIR) + "/scenarios/on_map.yaml";

LoadResult load_on_map(const std::string& text) {
  // As a file in scenarios/ (so maps/house.yaml resolves); never written there.
  return load_scenario_text(text, kPath, test::robots_dir());
}

::testing::AssertionResult fails_naming(const std::string& text, const char* key, const char* why) {
  const LoadResult r = load_on_map(text);
  if (r.ok) return ::testing::AssertionFailure() << "loaded";
  for (const std::string& f : {kPath + ":", std::string(key), std::string(why)}) {
    if (r.error.find(f) == std::string::npos) {
      return ::testing::AssertionFailure() << "lacks '" << f << "': " << r.error;
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(ScenarioLocalisationExpect, ReadsTheThreeBounds) {
  const LoadResult r = load_on_map(kOnMap + kKidnap + R"(expect:
  max_time_to_converge_s: 12.5
  max_relocalise_s: 60
  max_localisation_rmse_m: 0.08
)");
  ASSERT_TRUE(r.ok) << r.error;
  const ExpectSpec& e = r.scenario.expect;
  EXPECT_DOUBLE_EQ(e.max_time_to_converge_s.value_or(-1), 12.5);
  EXPECT_DOUBLE_EQ(e.max_relocalise_s.value_or(-1), 60.0);
  EXPECT_DOUBLE_EQ(e.max_localisation_rmse_m.value_or(-1), 0.08);
  EXPECT_TRUE(e.any());
}

TEST(ScenarioLocalisationExpect, BadBoundsNameTheirKey) {
  EXPECT_TRUE(
      fails_naming(kOnMap + "expect: {max_relocalise_s: 30}\n", "max_relocalise_s", "a kidnap"));
  EXPECT_TRUE(fails_naming(kOnMap + "expect: {max_localisation_rmse_m: 0}\n",
                           "max_localisation_rmse_m", "expected"));
  EXPECT_TRUE(fails_naming(kOnMap + "expect: {max_time_to_converge_s: -1}\n",
                           "max_time_to_converge_s", "expected"));
  // Localisation is scored only on a map.
  EXPECT_TRUE(test::fails_with(test::kMinimalYaml + "expect: {max_time_to_converge_s: 5}\n",
                               {"max_time_to_converge_s", "a map"}));
}

}  // namespace
}  // namespace carril::sim
