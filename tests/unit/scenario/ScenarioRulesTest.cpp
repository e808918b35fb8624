// Rules added by issue 7: explicit YAML tags, the end-stop expectation, physical ranges and
// derived quantities, size limits, zero-length tape, the start footprint and tape colours.
#include <gtest/gtest.h>

#include "host_sim/scenario/ColorCheck.hpp"
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
                         {"expect.max_end_stop_error_m: expected a number in (0, 10], got 0"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "expect: {max_end_stop_error_m: -1}\n",
                         {"expect.max_end_stop_error_m: expected a number in (0, 10], got -1"}));
}

// ---- Derived quantities ----

TEST(ScenarioRules, CameraMustSeeTheFloor) {
  // campero: 640x480, hfov 54.2 -> half vertical fov 20.9 deg; tilt 21 leaves 0.1 deg.
  EXPECT_TRUE(fails_with(edit(kFullYaml, "camera: {noise_std: 4.0}", "camera: {tilt_deg: 21}"),
                         {"robot.camera.tilt_deg: expected a tilt at least 1 deg more than half "
                          "the vertical field of view",
                          "got 21"}));
  EXPECT_TRUE(fails_with(edit(kFullYaml, "camera: {noise_std: 4.0}", "camera: {hfov_deg: 150}"),
                         {"robot.camera.tilt_deg: expected a tilt at least 1 deg more", "got 55"}));
  // z 5 m at tilt 14 deg: the image centre is 20.05 m away.
  EXPECT_TRUE(fails_with(
      edit(kFullYaml, "camera: {noise_std: 4.0}",
           "camera: {z_m: 5, tilt_deg: 14, hfov_deg: 20, width: 640, height: 32}"),
      {"robot.camera.tilt_deg: expected a tilt whose image centre meets the floor within 20 m",
       "got 14"}));
  const LoadResult ok = test::load(edit(kFullYaml, "camera: {noise_std: 4.0}",
                                        "camera: {z_m: 5, tilt_deg: 15, hfov_deg: 20, "
                                        "width: 640, height: 32}"));
  EXPECT_TRUE(ok.ok) << ok.error;
}

TEST(ScenarioRules, WheelsMustReachTheMissionSpeed) {
  // campero: radius 0.127 m; 2 rad/s -> 0.254 m/s < 0.8.
  const std::string yaml = edit(kFullYaml, "limits: {max_speed_mps: 1.2}",
                                "limits: {max_speed_mps: 1.2, max_wheel_speed_radps: 2}");
  EXPECT_TRUE(fails_with(yaml, {at_line(yaml, "speed_mps: 0.8") +
                                "mission.speed_mps: expected a speed the wheels can reach, at most "
                                "wheels.radius_m 0.127 x limits.max_wheel_speed_radps 2 = 0.254 "
                                "m/s, got 0.8"}));
  const std::string minimal =
      edit(kMinimalYaml, "robot: {preset: pioneer3at}",
           "robot: {preset: pioneer3at, limits: {max_wheel_speed_radps: 1}}");
  EXPECT_TRUE(fails_with(minimal, {"mission.speed_mps: expected a speed the wheels can reach",
                                   "got 0.5 (the preset's)"}));
}

// ---- Size limits ----

// `n` lines, each an alias of the first, whose points are an alias of one list of `pts` points.
std::string alias_bomb(int n, int pts) {
  std::string p = "[";
  for (int i = 0; i < pts; ++i) p += (i ? ", [" : "[") + std::to_string(i) + ", 0]";
  p += "]";
  std::string y = edit(kMinimalYaml, "  - {color: white, points: [[0, 0], [1, 0]]}\n",
                       "  - &l {color: white, points: " + p + "}\n");
  for (int i = 1; i < n; ++i) y += "  - *l\n";
  return y;
}

TEST(ScenarioRules, AliasBombHitsTheTapePointLimit) {
  // 256 lines x 5000 points = 1.28 million tape points from a 33 KB file.
  const std::string yaml = alias_bomb(256, 5000);
  EXPECT_TRUE(fails_with(yaml, {"lines[4].points: expected at most 20000 tape points in all "
                                "lines (the limit), got "}));
  // One list alone over the limit.
  EXPECT_TRUE(fails_with(alias_bomb(1, 20001), {"lines[0].points: expected at most 20000 tape "
                                                "points in all lines (the limit), got 20001 "
                                                "more, with 20000 left"}));
  const LoadResult at_limit = test::load(alias_bomb(4, 5000));
  EXPECT_TRUE(at_limit.ok) << at_limit.error;
}

TEST(ScenarioRules, ListsOverTheLimitRejectedBeforeReading) {
  std::string lines = edit(kMinimalYaml, "  - {color: white, points: [[0, 0], [1, 0]]}\n",
                           "  - &l {color: white, points: [[0, 0], [1, 0]]}\n");
  for (int i = 1; i < 257; ++i) lines += "  - *l\n";
  EXPECT_TRUE(
      fails_with(lines, {"lines: expected at most 256 lines (the limit), got a list of 257"}));
  auto many = [](const std::string& key, const std::string& item, int n) {
    std::string y = kMinimalYaml + key + ":\n  - &i " + item + "\n";
    for (int i = 1; i < n; ++i) y += "  - *i\n";
    return y;
  };
  EXPECT_TRUE(fails_with(many("marks", "{color: yellow, x: 5, y: 5}", 65),
                         {"marks: expected at most 64 marks (the limit), got a list of 65"}));
  EXPECT_TRUE(fails_with(many("obstacles", "{shape: cylinder, x: 5, y: 5, radius_m: 0.1}", 257),
                         {"obstacles: expected at most 256 obstacles (the limit), got a list of "
                          "257"}));
  EXPECT_TRUE(fails_with(many("walls", "{points: [[5, 5], [6, 5]]}", 257),
                         {"walls: expected at most 256 walls (the limit), got a list of 257"}));
  EXPECT_TRUE(fails_with(
      many("terrain", "{type: step, x: 5, y: 5, length_m: 1, width_m: 1, height_m: 0.1}", 257),
      {"terrain: expected at most 256 terrain items (the limit), got a list "
       "of 257"}));
  // Wall points in all: 200 walls of 21 points = 4200 > 4096.
  std::string pts = "[";
  for (int i = 0; i < 21; ++i) pts += (i ? ", [" : "[") + std::to_string(5 + i) + ", 5]";
  EXPECT_TRUE(fails_with(many("walls", "{points: " + pts + "]}", 200),
                         {"walls[195].points: expected at most 4096 wall points in all walls "
                          "(the limit), got "}));
  EXPECT_TRUE(test::load(many("walls", "{points: " + pts + "]}", 195)).ok);
}

TEST(ScenarioRules, BigArcsHitTheTapePointLimitBeforeDiscretising) {
  std::string y = edit(kMinimalYaml, "  - {color: white, points: [[0, 0], [1, 0]]}\n", "");
  for (int i = 0; i < 16; ++i) {
    y += "  - {color: white, arc: {center: [0, 0], radius_m: 100, start_deg: 0, end_deg: 3600}}\n";
  }
  // One such arc is 314161 points.
  EXPECT_TRUE(fails_with(y, {"lines[0].arc: expected at most 20000 tape points in all lines (the "
                             "limit), got 314161 more for this arc, with 20000 left"}));
  // 400 m of arc: 19985 points, under the limit.
  const LoadResult ok = test::load(
      edit(kMinimalYaml, "{color: white, points: [[0, 0], [1, 0]]}",
           "{color: white, arc: {center: [0, 0], radius_m: 100, start_deg: 0, end_deg: 229}}"));
  ASSERT_TRUE(ok.ok) << ok.error;
  EXPECT_LE(ok.scenario.lines[0].points.size(), 20000U);
}

// ---- Nonsense geometry ----

TEST(ScenarioRules, ZeroLengthTapeRejected) {
  EXPECT_TRUE(fails_with(edit(kMinimalYaml, "[[0, 0], [1, 0]]", "[[0, 0], [0.005, 0]]"),
                         {"lines[0].points: expected a tape at least 0.01 m long, got 0.005 m"}));
  const std::string dup = edit(kMinimalYaml, "[[0, 0], [1, 0]]", "[[0, 0], [1, 0], [1, 0]]");
  EXPECT_TRUE(fails_with(dup, {"lines[0].points[2]: expected a point at least 1 mm from the "
                               "previous one",
                               "got [1, 0]"}));
  EXPECT_TRUE(fails_with(
      edit(kMinimalYaml, "{color: white, points: [[0, 0], [1, 0]]}",
           "{color: white, arc: {center: [0, 0], radius_m: 0.05, start_deg: 0, end_deg: 1e-9}}"),
      {"lines[0].arc.end_deg: expected an arc at least 0.01 m long"}));
}

TEST(ScenarioRules, StartFootprintMustBeClear) {
  // pioneer3at, 0.508 x 0.497 at the origin, yaw 0.
  const std::string box = kMinimalYaml +
                          "obstacles:\n  - {shape: cylinder, x: 9, y: 9, radius_m: "
                          "0.5}\n  - {shape: box, x: 0.3, y: 0, size_m: [0.3, 0.3]}\n";
  EXPECT_TRUE(fails_with(box, {"robot.start: expected a start pose whose pioneer3at footprint "
                               "(0.508 x 0.497 m) is clear of obstacles, got x 0, y 0, yaw_deg 0 "
                               "(overlaps obstacles[1])"}));
  // Touching at x = 0.254 + 0.146 is not overlap.
  EXPECT_TRUE(test::load(edit(box, "x: 0.3, y: 0", "x: 0.41, y: 0")).ok);
  // A box rotated 45 deg, its corner reaching into the robot.
  EXPECT_TRUE(fails_with(edit(box, "x: 0.3, y: 0, size_m", "x: 0.45, y: 0, yaw_deg: 45, size_m"),
                         {"overlaps obstacles[1]"}));
  EXPECT_TRUE(
      test::load(edit(box, "x: 0.3, y: 0, size_m", "x: 0.47, y: 0, yaw_deg: 45, size_m")).ok);
  EXPECT_TRUE(
      fails_with(kMinimalYaml + "obstacles: [{shape: cylinder, x: 0.3, y: 0.3, radius_m: 0.1}]\n",
                 {"robot.start:", "overlaps obstacles[0]"}));
  EXPECT_TRUE(
      test::load(kMinimalYaml + "obstacles: [{shape: cylinder, x: 0.4, y: 0.4, radius_m: 0.1}]\n")
          .ok);
  // The robot rotated 90 deg: now 0.497 long in x.
  const std::string rotated = edit(kMinimalYaml, "robot: {preset: pioneer3at}",
                                   "robot: {preset: pioneer3at, start: {x: 0, y: 0, yaw_deg: 90}}");
  EXPECT_TRUE(
      test::load(rotated + "obstacles: [{shape: cylinder, x: 0, y: 0.36, radius_m: 0.1}]\n").ok);
  EXPECT_TRUE(fails_with(rotated + "obstacles: [{shape: cylinder, x: 0, y: 0.34, radius_m: 0.1}]\n",
                         {"overlaps obstacles[0]"}));
  // Walls: the second wall's second segment passes under the robot; a wall's thickness counts,
  // and so does its extension by half the thickness past each end.
  const std::string walls = kMinimalYaml +
                            "walls:\n  - {points: [[-5, -5], [5, -5]]}\n"
                            "  - {points: [[-5, 3], [-5, 0], [5, 0]], thickness_m: 0.2}\n";
  EXPECT_TRUE(
      fails_with(walls, {"robot.start:", "clear of walls", "(overlaps walls[1], segment 1)"}));
  EXPECT_TRUE(fails_with(kMinimalYaml + "walls: [{points: [[0.3, 0], [3, 0]], thickness_m: 0.2}]\n",
                         {"overlaps walls[0], segment 0"}));
  EXPECT_TRUE(
      test::load(kMinimalYaml + "walls: [{points: [[0.37, 0], [3, 0]], thickness_m: 0.2}]\n").ok);
}

// ---- Colours ----

TEST(ScenarioRules, TapeTheColourOfTheFloorRejected) {
  // White's window is V >= 170, S <= 60: a floor of 160 grey is white at x1.15 (184).
  const std::string grey = kMinimalYaml + "floor: {color: [160, 160, 160]}\n";
  EXPECT_TRUE(fails_with(grey, {"mission.line_color: expected a colour the detector tells from "
                                "floor.color [160, 160, 160] (its shade x1.05 = [168, 168, 168] is "
                                "inside the white window), got white"}));
  EXPECT_TRUE(test::load(kMinimalYaml + "floor: {color: [140, 140, 140]}\n").ok);
  // An [r, g, b] tape near the floor colour.
  const std::string rgb = edit(edit(kMinimalYaml, "line_color: white", "line_color: [90, 90, 110]"),
                               "{color: white,", "{color: [90, 90, 110],") +
                          "floor: {color: [90, 90, 90]}\n";
  EXPECT_TRUE(fails_with(rgb, {"mission.line_color:", "floor.color [90, 90, 90]",
                               "inside the [90, 90, 110] window), got [90, 90, 110]"}));
  // The end colour against the floor: a yellowish floor.
  EXPECT_TRUE(fails_with(kMinimalYaml + "floor: {color: [200, 190, 40]}\n",
                         {"mission.end_color: expected a colour the detector tells from "
                          "floor.color [200, 190, 40]",
                          "inside the yellow window), got yellow"}));
  // Black tape on a dark floor, at x0.85.
  const std::string black = edit(edit(kMinimalYaml, "line_color: white", "line_color: black"),
                                 "{color: white,", "{color: black,");
  EXPECT_TRUE(fails_with(black + "floor: {color: [80, 80, 80]}\n",
                         {"(its shade x0.85 = [68, 68, 68] is inside the black window)"}));
  EXPECT_TRUE(test::load(black + "floor: {color: [90, 90, 90]}\n").ok);
}

TEST(ScenarioRules, TapeThatReadsAsTheEndMarkRejected) {
  const std::string same =
      edit(kMinimalYaml, "line_color: white", "line_color: white, end_color: white");
  EXPECT_TRUE(fails_with(same, {"mission.end_color: expected an end colour the detector tells from "
                                "mission.line_color white (the tape falls in the end window), got "
                                "white"}));
  const std::string orange =
      edit(kMinimalYaml, "line_color: white", "line_color: white, end_color: [255, 250, 240]");
  EXPECT_TRUE(fails_with(orange, {"mission.end_color:", "got [255, 250, 240]"}));
  // Yellow tape with a [255, 200, 0] end colour: hue 23 is inside the yellow window.
  const std::string yellow =
      edit(edit(kMinimalYaml, "line_color: white", "line_color: yellow, end_color: [255, 200, 0]"),
           "{color: white,", "{color: yellow,");
  EXPECT_TRUE(fails_with(yellow, {"mission.end_color:", "got [255, 200, 0]"}));
  // Light grey end on white tape: the grey is in white's window, white not in the grey's.
  const std::string grey_end =
      edit(kMinimalYaml, "line_color: white", "line_color: white, end_color: [180, 180, 180]") +
      "floor: {color: [60, 60, 60]}\n";
  EXPECT_TRUE(fails_with(grey_end, {"mission.end_color:",
                                    "(the end colour falls in the tape "
                                    "window), got [180, 180, 180]"}));
}

TEST(ScenarioRules, DetectorThresholdIsTheSimulatorsMapping) {
  fw::ColorThreshold preset;
  ASSERT_TRUE(fw::color_preset("red", preset));
  const fw::ColorThreshold t = detector_threshold("red", {255, 0, 0});
  EXPECT_EQ(t.h_lo, preset.h_lo);
  EXPECT_EQ(t.h_hi, preset.h_hi);
  EXPECT_EQ(t.v_lo, preset.v_lo);
  const fw::ColorThreshold a = detector_threshold("[10, 200, 30]", {10, 200, 30});
  const fw::ColorThreshold b = fw::threshold_around_rgb(10, 200, 30);
  EXPECT_EQ(a.h_lo, b.h_lo);
  EXPECT_EQ(a.h_hi, b.h_hi);
  EXPECT_EQ(a.s_lo, b.s_lo);
  EXPECT_EQ(a.v_lo, b.v_lo);
}

}  // namespace
}  // namespace carril::sim
