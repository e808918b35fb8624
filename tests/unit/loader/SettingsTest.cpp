// The table of tunable fields: every key is documented, and settings made in code are checked.
#include "loader/Settings.hpp"

#include <gtest/gtest.h>

#include "firmware/app/FirmwareConfig.hpp"
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
  ASSERT_TRUE(
      explain_with_settings(s, "strategy.pid_straight: gains kp, ki, kd must be >= 0", out));
  EXPECT_EQ(out, "m.yaml:4: strategy_gains.pid_straight.kd: gains kp, ki, kd must be >= 0");
  // A field the settings did not touch, and one that merely shares a prefix.
  EXPECT_FALSE(explain_with_settings(s, "strategy.speed_mps: 9 m/s, expected 0.01 to 5 m/s", out));
  EXPECT_FALSE(explain_with_settings(s, "strategy.pid: x", out));
}

}  // namespace
}  // namespace carril::loader
