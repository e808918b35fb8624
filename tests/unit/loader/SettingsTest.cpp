// The table of tunable fields: every key is documented, and settings made in code are checked.
#include "loader/Settings.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "firmware/app/FirmwareConfig.hpp"
#include "loader/FirmwareConfigBuilder.hpp"
#include "loader/SettingsDoc.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

TEST(Settings, EveryKeyIsDocumented) {
  const std::string doc = test::read_text(test::source_path("docs/configuration.md"));
  ASSERT_FALSE(doc.empty());
  for (const SettingFile file : {SettingFile::Mission, SettingFile::Tuning}) {
    const auto keys = setting_keys(file);
    EXPECT_FALSE(keys.empty());
    for (const std::string& key : keys) {
      EXPECT_NE(doc.find("`" + key + "`"), std::string::npos) << key << " is not in the docs";
    }
  }
}

TEST(Settings, MissionAndTuningShareNoKey) {
  for (const std::string& m : setting_keys(SettingFile::Mission)) {
    for (const std::string& t : setting_keys(SettingFile::Tuning)) EXPECT_NE(m, t);
  }
}

TEST(Settings, AppliedInOrderAndUnknownKeysRejected) {
  fw::FirmwareConfig c;
  std::string error;
  ASSERT_TRUE(apply_settings(
      {{"detector.decimation", 4.0, "t.yaml", 3}, {"behavior.avoid.speed_mps", 0.2, "m.yaml", 9}},
      c, error))
      << error;
  EXPECT_EQ(c.camera.detector.decimation, 4);
  EXPECT_EQ(c.follow_line.behavior.avoid.speed_mps, 0.2);
  EXPECT_FALSE(apply_settings({{"detector.colour", 1.0, "t.yaml", 7}}, c, error));
  EXPECT_EQ(error, "t.yaml:7: detector.colour: not a tunable field");
}

TEST(Settings, ExplainsOnlyWhatASettingSet) {
  const std::vector<Setting> s = {{"strategy_gains.pid_straight.kd", -1.0, "m.yaml", 4}};
  std::string out;
  ASSERT_TRUE(explain_with_settings(s, "strategy.pid_straight.kd: -1 x, expected 0 to 100 x", out));
  EXPECT_EQ(out, "m.yaml:4: strategy_gains.pid_straight.kd: -1 x, expected 0 to 100 x");
  // A message about the struct the field is in (a check across its fields) is traced to it too.
  ASSERT_TRUE(explain_with_settings(s, "strategy.pid_straight: gains too high", out));
  EXPECT_EQ(out, "m.yaml:4: strategy_gains.pid_straight.kd: gains too high");
  // A field the settings did not touch, and one that merely shares a prefix.
  EXPECT_FALSE(explain_with_settings(s, "strategy.speed_mps: 9 m/s, expected 0.01 to 5 m/s", out));
  EXPECT_FALSE(explain_with_settings(s, "strategy.pid: x", out));
}

// docs/configuration.md's two settings tables are what the code's tables give (regenerate them
// with build/host/tools/settings_doc/carril_settings_doc docs/configuration.md).
TEST(Settings, DocsAreTheTables) {
  const std::string doc = test::read_text(test::source_path("docs/configuration.md"));
  std::string regenerated, error;
  ASSERT_TRUE(regenerate_settings_doc(doc, regenerated, error)) << error;
  EXPECT_TRUE(regenerated == doc)
      << "docs/configuration.md's settings tables differ from the code's; run "
         "build/host/tools/settings_doc/carril_settings_doc docs/configuration.md";
  EXPECT_NE(doc.find("| `runner.obstacle.stop_m` | m | 0.45 | [0.05, 5] |"), std::string::npos);
}

TEST(Settings, TheDocMarkersAreChecked) {
  std::string out, error;
  EXPECT_FALSE(regenerate_settings_doc("<!-- settings: tuning -->\nx\n", out, error));
  EXPECT_EQ(error, "settings marker 'tuning' is not closed by <!-- end of settings -->");
  EXPECT_FALSE(
      regenerate_settings_doc("<!-- settings: robot -->\n<!-- end of settings -->\n", out, error));
  EXPECT_EQ(error, "settings marker 'robot': expected mission or tuning");
  EXPECT_FALSE(
      regenerate_settings_doc("<!-- settings: tuning -->\n<!-- end of settings -->\n", out, error));
  EXPECT_EQ(error, "no mission settings marker");
}

// Each row is whole: a unit, a one-line meaning, a range that holds its default.
TEST(Settings, EveryRowIsWhole) {
  for (const SettingFile file : {SettingFile::Mission, SettingFile::Tuning}) {
    for (const SettingInfo& s : settings_info(file)) {
      SCOPED_TRACE(s.key);
      EXPECT_TRUE(s.info.tunable);
      EXPECT_NE(std::string(s.info.unit), "");
      const std::string d = s.info.description;
      EXPECT_NE(d, "");
      EXPECT_EQ(d.find_first_of("|\n"), std::string::npos);
      EXPECT_LE(s.info.min, s.info.max);
      EXPECT_GE(s.default_value, s.info.min);
      EXPECT_LE(s.default_value, s.info.max);
      EXPECT_TRUE(s.key.ends_with(s.info.name));
      EXPECT_TRUE(s.field.ends_with(s.info.name));
    }
  }
}

// validate() follows from the table: for every key of either file, a value just outside the
// row's range, set from a file, is refused when the configuration is built, and the message names
// the file, line and key with the row's range; the row's own bounds are taken.
TEST(Settings, ValidateChecksEveryRowsRange) {
  const RobotSpec r = test::robot("campero");
  MissionSpec m;
  std::string error;
  ASSERT_TRUE(load_mission(test::source_path("config/missions/follow_line.yaml"), r, m, error))
      << error;
  const auto build = [&](const std::string& key, double v) {
    Tuning t;
    t.settings = {{key, v, "t.yaml", 5}};
    return build_firmware_config(r, m, &t);
  };
  int rows = 0;
  for (const SettingFile file : {SettingFile::Mission, SettingFile::Tuning}) {
    for (const SettingInfo& s : settings_info(file)) {
      SCOPED_TRACE(s.key);
      ++rows;
      const double step = s.integer ? 1.0 : std::max(1e-3, 1e-3 * std::fabs(s.info.max));
      for (const double bad : {s.info.min - step, s.info.max + step}) {
        const BuildResult b = build(s.key, bad);
        EXPECT_FALSE(b.ok) << bad;
        EXPECT_EQ(b.error.rfind("t.yaml:5: " + s.key + ": ", 0), 0u) << b.error;
        EXPECT_NE(b.firmware_error.find(s.field + ": "), std::string::npos) << b.firmware_error;
      }
      for (const double good : {s.info.min, s.info.max}) {
        const BuildResult b = build(s.key, good);
        // A bound may still be refused by a check across fields, never by its own range.
        const bool own_range = b.firmware_error.rfind(s.field + ": ", 0) == 0 &&
                               b.firmware_error.find(", expected ") != std::string::npos;
        EXPECT_FALSE(own_range) << good << ": " << b.firmware_error;
      }
    }
  }
  EXPECT_GT(rows, 80);
}

}  // namespace
}  // namespace carril::loader
