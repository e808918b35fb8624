// Mission files: the mission keys with the scenario section's checks, and the optional
// behavior:, strategy_gains: and tape_preview_m settings; errors name the file, line and key.
#include "loader/MissionLoader.hpp"

#include <gtest/gtest.h>

#include "loader/FirmwareConfigBuilder.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::edit;
using test::robot;
using test::source_path;
using test::write_file;

const std::string kMission = R"(type: follow_line
strategy: marks
line_color: white
end_color: yellow
speed_mps: 0.5
tape_preview_m: 0.8
behavior:
  end_speed_mps: 0.2
  lost_frames: 5
  avoid: {clearance_m: 0.4}
strategy_gains:
  lp_k_lateral: 2.0
  pid_curve: {kp: 2.5, speed_mps: 0.3}
)";

// Loads `text` (written to a file) for `preset`; on failure returns the error.
struct Loaded {
  bool ok = false;
  MissionSpec mission;
  std::string error;
  std::string path;
};

Loaded load(const std::string& text, const std::string& preset = "campero") {
  Loaded l;
  l.path = write_file("mission.yaml", text);
  l.ok = load_mission(l.path, robot(preset), l.mission, l.error);
  return l;
}

// The error of loading `text`, which must fail.
std::string error_of(const std::string& text, const std::string& preset = "campero") {
  const Loaded l = load(text, preset);
  EXPECT_FALSE(l.ok) << "loaded";
  return l.error;
}

std::string at(const std::string& path, int line) {
  return path + ":" + std::to_string(line) + ": ";
}

TEST(MissionLoader, ShippedMissionLoads) {
  MissionSpec m;
  std::string error;
  const std::string path = source_path("config/missions/follow_line.yaml");
  ASSERT_TRUE(load_mission(path, robot("campero"), m, error)) << error;
  EXPECT_EQ(m.strategy, "line_priority");
  EXPECT_EQ(m.line_color_name, "white");
  EXPECT_EQ(m.end_color_name, "yellow");
  EXPECT_EQ(m.speed_mps, 0.5);
  EXPECT_EQ(m.source_path, path);
  EXPECT_TRUE(m.settings.empty());
}

TEST(MissionLoader, SettingsReachTheirFields) {
  const Loaded l = load(kMission);
  ASSERT_TRUE(l.ok) << l.error;
  ASSERT_EQ(l.mission.settings.size(), 7U);
  const BuildResult b = build_firmware_config(robot("campero"), l.mission);
  ASSERT_TRUE(b.ok) << b.error;
  const fw::FollowLineConfig& f = b.config.follow_line;
  EXPECT_EQ(f.tape_preview_m, 0.8);
  EXPECT_EQ(f.behavior.end_speed_mps, 0.2);
  EXPECT_EQ(f.behavior.lost_frames, 5);
  EXPECT_EQ(f.behavior.avoid.clearance_m, 0.4);
  EXPECT_EQ(f.strategy.lp_k_lateral, 2.0);
  EXPECT_EQ(f.strategy.pid_curve.kp, 2.5);
  EXPECT_EQ(f.strategy.pid_curve.speed_mps, 0.3);  // the setting wins over 0.8 x speed
  EXPECT_EQ(f.strategy.pid_straight.speed_mps, 0.5);
  EXPECT_EQ(f.behavior.end_gain, fw::BehaviorConfig{}.end_gain);  // not set: the default
}

TEST(MissionLoader, SpeedDefaultsToTheRobotsCruiseSpeed) {
  const Loaded l = load(edit(kMission, "speed_mps: 0.5\n", ""), "pioneer3at");
  ASSERT_TRUE(l.ok) << l.error;
  EXPECT_EQ(l.mission.speed_mps, robot("pioneer3at").cruise_speed_mps);
}

TEST(MissionLoader, UnknownKeysListTheAllowedOnes) {
  const Loaded top = load(edit(kMission, "behavior:", "behaviour:"));
  EXPECT_EQ(top.error, at(top.path, 7) +
                           "behaviour: unknown key (allowed: type, strategy, line_color, "
                           "end_color, speed_mps, tape_preview_m, behavior, strategy_gains)");
  const Loaded nested = load(edit(kMission, "clearance_m", "clearence_m"));
  EXPECT_EQ(nested.error, at(nested.path, 10) +
                              "behavior.avoid.clearence_m: unknown key (allowed: "
                              "corridor_margin_m, clearance_m, speed_mps, emergency_m, "
                              "max_lateral_m, blocked_timeout_s, lookahead_m)");
  const Loaded gains = load(edit(kMission, "pid_curve: {kp", "pid_curve: {kpp"));
  EXPECT_EQ(gains.error, at(gains.path, 13) +
                             "strategy_gains.pid_curve.kpp: unknown key (allowed: kp, ki, kd, "
                             "speed_mps)");
  // The strategy and its speed are the mission's own keys, not gains.
  const Loaded speed = load(edit(kMission, "lp_k_lateral: 2.0", "speed_mps: 0.4"));
  EXPECT_NE(speed.error.find(at(speed.path, 12) + "strategy_gains.speed_mps: unknown key"),
            std::string::npos)
      << speed.error;
}

TEST(MissionLoader, WrongTypesNameFileLineAndKey) {
  const Loaded frac = load(edit(kMission, "lost_frames: 5", "lost_frames: 2.5"));
  EXPECT_EQ(frac.error, at(frac.path, 9) + "behavior.lost_frames: expected an integer, got 2.5");
  const Loaded text = load(edit(kMission, "lp_k_lateral: 2.0", "lp_k_lateral: fast"));
  EXPECT_EQ(text.error,
            at(text.path, 12) + "strategy_gains.lp_k_lateral: expected a number, got \"fast\"");
  const Loaded quoted = load(edit(kMission, "tape_preview_m: 0.8", "tape_preview_m: \"0.8\""));
  EXPECT_EQ(quoted.error, at(quoted.path, 6) + "tape_preview_m: expected a number, got \"0.8\"");
  const Loaded scalar = load(edit(kMission, "  avoid: {clearance_m: 0.4}", "  avoid: 3"));
  EXPECT_EQ(scalar.error, at(scalar.path, 10) + "behavior.avoid: expected a map, got \"3\"");
  const Loaded inf = load(edit(kMission, "end_speed_mps: 0.2", "end_speed_mps: .inf"));
  EXPECT_EQ(inf.error,
            at(inf.path, 8) + "behavior.end_speed_mps: expected a finite number, got .inf");
}

TEST(MissionLoader, OutOfRangeSettingsNameFileLineAndKeyWhenBuilt) {
  const Loaded l = load(edit(kMission, "end_speed_mps: 0.2", "end_speed_mps: 5"));
  ASSERT_TRUE(l.ok) << l.error;
  const BuildResult b = build_firmware_config(robot("campero"), l.mission);
  ASSERT_FALSE(b.ok);
  EXPECT_EQ(b.error, at(l.path, 8) + "behavior.end_speed_mps: 5 m/s, expected 0.01 to 2 m/s");
  const Loaded gain = load(edit(kMission, "{kp: 2.5", "{kp: -1"));
  ASSERT_TRUE(gain.ok) << gain.error;
  const BuildResult g = build_firmware_config(robot("campero"), gain.mission);
  ASSERT_FALSE(g.ok);
  EXPECT_EQ(g.error, at(gain.path, 13) +
                         "strategy_gains.pid_curve.kp: -1 rad/s per unit error, expected 0 to 100 "
                         "rad/s per unit error");
}

TEST(MissionLoader, MissionChecksAreTheScenariosWithTheRobotNamed) {
  EXPECT_NE(error_of(edit(kMission, "strategy: marks", "strategy: line_priority"), "pioneer3at")
                .find(":2: strategy: expected marks or pid (line_priority needs a mecanum drive; "
                      "preset pioneer3at is differential), got \"line_priority\""),
            std::string::npos);
  EXPECT_NE(error_of(edit(kMission, "speed_mps: 0.5", "speed_mps: 0.9"), "pioneer3at")
                .find(":5: speed_mps: expected a number in (0, the robot's "
                      "limits.max_speed_mps = 0.7], got 0.9"),
            std::string::npos);
  EXPECT_NE(error_of(edit(kMission, "end_color: yellow", "end_color: white"))
                .find(":4: end_color: expected an end colour the detector tells from line_color "
                      "white"),
            std::string::npos);
  EXPECT_NE(
      error_of(edit(kMission, "strategy: marks\n", "")).find("strategy: missing required key"),
      std::string::npos);
  EXPECT_NE(error_of(edit(kMission, "type: follow_line", "type: mowing"))
                .find(":1: type: expected one of"),
            std::string::npos);
  // coverage has its own keys too: a follow_line key in a coverage mission is named.
  EXPECT_NE(error_of(edit(kMission, "type: follow_line", "type: coverage")).find("strategy"),
            std::string::npos);
  // goto has its own keys: a follow_line key in a goto mission is named as unknown.
  EXPECT_NE(error_of("type: goto\ngoal: {x: 1.0, y: 2.0, yaw_deg: 0.0}\nstrategy: pid\n")
                .find("strategy"),
            std::string::npos);
  EXPECT_NE(error_of("type: goto\ngoal: {x: 1.0, yaw_deg: 0.0}\n").find("goal.y"),
            std::string::npos);
  EXPECT_NE(error_of("type: goto\ngoal: {x: 1.0, y: 0.0, yaw_deg: 0.0}\nfollower: dwa\n")
                .find("follower: expected"),
            std::string::npos);
}

TEST(MissionLoader, ReadsAGotoMission) {
  const Loaded l = load(
      "type: goto\ngoal: {x: 3.5, y: -1.0, yaw_deg: 90.0}\nfollower: vff\n"
      "allow_unknown: false\nspeed_mps: 0.4\n",
      "pioneer3at");
  ASSERT_TRUE(l.ok) << l.error;
  const MissionSpec& m = l.mission;
  EXPECT_EQ(m.type, "goto");
  EXPECT_DOUBLE_EQ(m.goal_x_m, 3.5);
  EXPECT_DOUBLE_EQ(m.goal_y_m, -1.0);
  EXPECT_DOUBLE_EQ(m.goal_yaw_deg, 90.0);
  EXPECT_EQ(m.follower, "vff");
  EXPECT_FALSE(m.allow_unknown);
  EXPECT_DOUBLE_EQ(m.speed_mps, 0.4);
}

TEST(MissionLoader, MissingFileAndSyntaxErrors) {
  MissionSpec m;
  m.speed_mps = 0.123;
  std::string error;
  EXPECT_FALSE(load_mission("/nonexistent/mission.yaml", robot("campero"), m, error));
  EXPECT_EQ(error, "/nonexistent/mission.yaml: cannot open");
  EXPECT_EQ(m.speed_mps, 0.123);  // untouched on failure
  const Loaded syntax = load("type: [follow_line\n");
  EXPECT_NE(syntax.error.find(syntax.path + ":"), std::string::npos);
  EXPECT_NE(syntax.error.find("invalid YAML"), std::string::npos) << syntax.error;
}

}  // namespace
}  // namespace carril::loader
