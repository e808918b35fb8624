// Valid files: values, units, defaults, preset merging, arc discretisation, presets on disk.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "host_sim/scenario/ScenarioLoader.hpp"
#include "tests/unit/scenario/ScenarioTestUtil.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::sim {
namespace {

using test::edit;
using test::kFullYaml;
using test::kMinimalYaml;
using test::load;

using fw::kPi;  // the one pi, firmware/core/Geometry.hpp

double dist(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

TEST(ScenarioLoader, FullFileParsesIntoValues) {
  const LoadResult r = load(kFullYaml);
  ASSERT_TRUE(r.ok) << r.error;
  const Scenario& s = r.scenario;
  EXPECT_EQ(s.source_path, test::kPath);
  EXPECT_EQ(s.name, "corners-1_b");
  EXPECT_EQ(s.description, "test scenario");
  EXPECT_DOUBLE_EQ(s.duration_s, 240.0);
  EXPECT_EQ(s.seed, 7U);
  EXPECT_EQ(s.floor, (Rgb{90, 91, 92}));

  EXPECT_EQ(s.robot.preset, "campero");
  EXPECT_EQ(s.robot.drive, DriveType::Mecanum);
  EXPECT_DOUBLE_EQ(s.robot.start.x, 1.0);
  EXPECT_DOUBLE_EQ(s.robot.start.y, -2.0);
  EXPECT_DOUBLE_EQ(s.robot.start.yaw_rad, kPi / 2);

  EXPECT_EQ(s.mission.type, "follow_line");
  EXPECT_EQ(s.mission.strategy, "line_priority");
  EXPECT_EQ(s.mission.line_color, (Rgb{255, 255, 255}));
  EXPECT_EQ(s.mission.line_color_name, "white");
  EXPECT_EQ(s.mission.end_color, (Rgb{0, 0, 255}));
  EXPECT_EQ(s.mission.end_color_name, "[0, 0, 255]");
  EXPECT_DOUBLE_EQ(s.mission.speed_mps, 0.8);

  ASSERT_EQ(s.lines.size(), 3U);
  EXPECT_EQ(s.lines[0].color, (Rgb{255, 255, 255}));
  EXPECT_DOUBLE_EQ(s.lines[0].width_m, 0.05);
  EXPECT_FALSE(s.lines[0].from_arc);
  ASSERT_EQ(s.lines[0].points.size(), 3U);
  EXPECT_DOUBLE_EQ(s.lines[0].points[2].x, 6.0);
  EXPECT_DOUBLE_EQ(s.lines[0].points[2].y, 4.0);
  EXPECT_EQ(s.lines[1].color, (Rgb{255, 0, 0}));
  EXPECT_DOUBLE_EQ(s.lines[1].width_m, 0.04);
  EXPECT_TRUE(s.lines[1].from_arc);
  EXPECT_DOUBLE_EQ(s.lines[2].width_m, 0.06);

  ASSERT_EQ(s.marks.size(), 1U);
  EXPECT_EQ(s.marks[0].color, (Rgb{255, 255, 0}));
  EXPECT_DOUBLE_EQ(s.marks[0].center.x, 6.0);
  EXPECT_DOUBLE_EQ(s.marks[0].center.y, 4.3);
  EXPECT_DOUBLE_EQ(s.marks[0].radius_m, 0.2);

  ASSERT_EQ(s.obstacles.size(), 2U);
  EXPECT_EQ(s.obstacles[0].shape, ObstacleShape::Box);
  EXPECT_DOUBLE_EQ(s.obstacles[0].center.x, 3.0);
  EXPECT_DOUBLE_EQ(s.obstacles[0].center.y, 0.5);
  EXPECT_DOUBLE_EQ(s.obstacles[0].yaw_rad, kPi / 6);
  EXPECT_DOUBLE_EQ(s.obstacles[0].size_x_m, 1.0);
  EXPECT_DOUBLE_EQ(s.obstacles[0].size_y_m, 2.0);
  EXPECT_EQ(s.obstacles[1].shape, ObstacleShape::Cylinder);
  EXPECT_DOUBLE_EQ(s.obstacles[1].radius_m, 0.5);

  ASSERT_EQ(s.walls.size(), 1U);
  EXPECT_EQ(s.walls[0].points.size(), 3U);
  EXPECT_DOUBLE_EQ(s.walls[0].thickness_m, 0.2);

  ASSERT_EQ(s.terrain.size(), 2U);
  EXPECT_EQ(s.terrain[0].type, TerrainType::Ramp);
  EXPECT_DOUBLE_EQ(s.terrain[0].yaw_rad, kPi / 4);
  EXPECT_DOUBLE_EQ(s.terrain[0].angle_deg, 5.0);
  EXPECT_DOUBLE_EQ(s.terrain[0].length_m, 2.0);
  EXPECT_EQ(s.terrain[1].type, TerrainType::Step);
  EXPECT_DOUBLE_EQ(s.terrain[1].yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(s.terrain[1].height_m, 0.2);
  EXPECT_DOUBLE_EQ(s.terrain[1].width_m, 1.25);

  EXPECT_EQ(s.expect.end_reached, true);
  EXPECT_EQ(s.expect.max_collisions, 0);
  EXPECT_EQ(s.expect.max_cross_track_rms_m, 0.05);
  EXPECT_EQ(s.expect.min_progress, 1.0);
  EXPECT_EQ(s.expect.min_laps, 1);
  EXPECT_TRUE(s.expect.any());
}

TEST(ScenarioLoader, OverridesMergeOntoPreset) {
  RobotSpec preset;
  std::string error;
  ASSERT_TRUE(load_robot_preset(test::robots_dir() + "/campero.yaml", preset, error)) << error;
  const LoadResult r = load(kFullYaml);
  ASSERT_TRUE(r.ok) << r.error;
  const RobotSpec& robot = r.scenario.robot;
  // Overridden keys.
  EXPECT_DOUBLE_EQ(robot.camera.noise_std, 4.0);
  EXPECT_EQ(robot.lidar.beams, 271);
  EXPECT_DOUBLE_EQ(robot.limits.max_speed_mps, 1.2);
  // Everything else keeps the preset's values.
  EXPECT_DOUBLE_EQ(robot.camera.z_m, preset.camera.z_m);
  EXPECT_DOUBLE_EQ(robot.camera.tilt_deg, preset.camera.tilt_deg);
  EXPECT_EQ(robot.camera.width, preset.camera.width);
  EXPECT_DOUBLE_EQ(robot.lidar.fov_deg, preset.lidar.fov_deg);
  EXPECT_DOUBLE_EQ(robot.lidar.range_max_m, preset.lidar.range_max_m);
  EXPECT_DOUBLE_EQ(robot.limits.max_yaw_rate_radps, preset.limits.max_yaw_rate_radps);
  EXPECT_DOUBLE_EQ(robot.wheel_radius_m, preset.wheel_radius_m);
  EXPECT_DOUBLE_EQ(robot.cruise_speed_mps, preset.cruise_speed_mps);
}

TEST(ScenarioLoader, MinimalFileGetsDefaults) {
  const LoadResult r = load(kMinimalYaml);
  ASSERT_TRUE(r.ok) << r.error;
  const Scenario& s = r.scenario;
  EXPECT_EQ(s.description, "");
  EXPECT_EQ(s.seed, 0U);
  EXPECT_EQ(s.floor, (Rgb{128, 128, 128}));
  EXPECT_EQ(s.robot.preset, "pioneer3at");
  EXPECT_EQ(s.robot.drive, DriveType::Differential);
  EXPECT_DOUBLE_EQ(s.robot.start.x, 0.0);
  EXPECT_DOUBLE_EQ(s.robot.start.y, 0.0);
  EXPECT_DOUBLE_EQ(s.robot.start.yaw_rad, 0.0);
  EXPECT_EQ(s.mission.end_color, (Rgb{255, 255, 0}));
  EXPECT_EQ(s.mission.end_color_name, "yellow");
  EXPECT_DOUBLE_EQ(s.mission.speed_mps, s.robot.cruise_speed_mps);  // default from preset
  EXPECT_DOUBLE_EQ(s.mission.speed_mps, 0.5);
  ASSERT_EQ(s.lines.size(), 1U);
  EXPECT_DOUBLE_EQ(s.lines[0].width_m, 0.05);
  EXPECT_TRUE(s.marks.empty());
  EXPECT_TRUE(s.obstacles.empty());
  EXPECT_TRUE(s.walls.empty());
  EXPECT_TRUE(s.terrain.empty());
  EXPECT_FALSE(s.expect.any());
}

TEST(ScenarioLoader, OptionalDefaultsInsideItems) {
  const LoadResult r = load(std::string(kMinimalYaml) +
                            "marks: [{color: red, x: 1, y: 2}]\n"
                            "obstacles: [{shape: box, x: 1, y: 2, size_m: [0.5, 0.25]}]\n"
                            "walls: [{points: [[2, 2], [3, 3]]}]\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_DOUBLE_EQ(r.scenario.marks[0].radius_m, 0.15);
  EXPECT_DOUBLE_EQ(r.scenario.obstacles[0].yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(r.scenario.walls[0].thickness_m, 0.1);
}

TEST(ScenarioLoader, RgbListLineColourMatchesLines) {
  const LoadResult r = load(edit(edit(kMinimalYaml, "line_color: white", "line_color: [1, 2, 3]"),
                                 "color: white", "color: [1, 2, 3]"));
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.mission.line_color, (Rgb{1, 2, 3}));
  EXPECT_EQ(r.scenario.mission.line_color_name, "[1, 2, 3]");
}

TEST(ScenarioLoader, RobotPresetsLoad) {
  RobotSpec campero;
  RobotSpec pioneer;
  std::string error;
  ASSERT_TRUE(load_robot_preset(test::robots_dir() + "/campero.yaml", campero, error)) << error;
  ASSERT_TRUE(load_robot_preset(test::robots_dir() + "/pioneer3at.yaml", pioneer, error)) << error;
  EXPECT_EQ(campero.preset, "campero");
  EXPECT_EQ(campero.drive, DriveType::Mecanum);
  EXPECT_DOUBLE_EQ(campero.length_m, 0.98);
  EXPECT_DOUBLE_EQ(campero.mass_kg, 110.0);
  EXPECT_DOUBLE_EQ(campero.wheel_radius_m, 0.127);
  EXPECT_DOUBLE_EQ(campero.camera.tilt_deg, 55.0);
  EXPECT_EQ(campero.camera.width, 640);
  EXPECT_DOUBLE_EQ(campero.lidar.yaw_deg, -45.0);  // the lidar keeps degrees (LidarSpec)
  EXPECT_EQ(campero.lidar.beams, 541);
  EXPECT_DOUBLE_EQ(campero.limits.max_wheel_accel_radps2, 25.0);
  EXPECT_DOUBLE_EQ(campero.control_rate_hz, 100.0);
  EXPECT_EQ(pioneer.preset, "pioneer3at");
  EXPECT_EQ(pioneer.drive, DriveType::Differential);
  EXPECT_DOUBLE_EQ(pioneer.track_m, 0.394);
  EXPECT_DOUBLE_EQ(pioneer.lidar.range_max_m, 8.0);
  EXPECT_DOUBLE_EQ(pioneer.limits.max_speed_mps, 0.7);
}

TEST(ScenarioLoader, DefaultRobotsDirHasThePresets) {
  EXPECT_TRUE(std::filesystem::exists(default_robots_dir() + "/campero.yaml"));
  EXPECT_TRUE(std::filesystem::exists(default_robots_dir() + "/pioneer3at.yaml"));
}

TEST(ScenarioLoader, ColourNames) {
  Rgb c;
  ASSERT_TRUE(color_from_name("yellow", c));
  EXPECT_EQ(c, (Rgb{255, 255, 0}));
  ASSERT_TRUE(color_from_name("blue", c));
  EXPECT_EQ(c, (Rgb{0, 0, 255}));
  EXPECT_FALSE(color_from_name("Yellow", c));
  EXPECT_FALSE(color_from_name("purple", c));
}

// ---- Arcs ----

std::vector<Vec2> arc_points(double cx, double cy, double r, double start, double end) {
  const std::string arc = "{color: white, arc: {center: [" + std::to_string(cx) + ", " +
                          std::to_string(cy) + "], radius_m: " + std::to_string(r) +
                          ", start_deg: " + std::to_string(start) +
                          ", end_deg: " + std::to_string(end) + "}}";
  const LoadResult res = load(edit(kMinimalYaml, "{color: white, points: [[0, 0], [1, 0]]}", arc));
  EXPECT_TRUE(res.ok) << res.error;
  if (!res.ok) return {};
  EXPECT_TRUE(res.scenario.lines[0].from_arc);
  return res.scenario.lines[0].points;
}

void check_arc(const std::vector<Vec2>& pts, Vec2 c, double r, double start_deg, double end_deg) {
  ASSERT_GE(pts.size(), 2U);
  const double a0 = start_deg * kPi / 180.0;
  const double a1 = end_deg * kPi / 180.0;
  // Endpoints exact.
  EXPECT_DOUBLE_EQ(pts.front().x, c.x + r * std::cos(a0));
  EXPECT_DOUBLE_EQ(pts.front().y, c.y + r * std::sin(a0));
  EXPECT_DOUBLE_EQ(pts.back().x, c.x + r * std::cos(a1));
  EXPECT_DOUBLE_EQ(pts.back().y, c.y + r * std::sin(a1));
  // On the circle, no more than 2 cm apart, and not needlessly dense.
  const auto expected_segments = static_cast<std::size_t>(std::ceil(std::abs(a1 - a0) * r / 0.02));
  EXPECT_EQ(pts.size(), expected_segments + 1);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(dist(pts[i], c), r, 1e-9);
    if (i > 0) EXPECT_LE(dist(pts[i], pts[i - 1]), 0.02 + 1e-9);
  }
}

// Sign of the z component of (p1 - c) x (p2 - c): + counter-clockwise.
double turn(Vec2 c, Vec2 p1, Vec2 p2) {
  return (p1.x - c.x) * (p2.y - c.y) - (p1.y - c.y) * (p2.x - c.x);
}

TEST(ScenarioLoader, ArcCounterClockwiseWhenEndAboveStart) {
  const auto pts = arc_points(1.0, 2.0, 3.0, -90.0, 270.0);
  check_arc(pts, {1.0, 2.0}, 3.0, -90.0, 270.0);
  ASSERT_GE(pts.size(), 3U);
  for (std::size_t i = 1; i < pts.size(); ++i) EXPECT_GT(turn({1.0, 2.0}, pts[i - 1], pts[i]), 0);
}

TEST(ScenarioLoader, ArcClockwiseWhenEndBelowStart) {
  const auto pts = arc_points(-1.0, 0.5, 0.7, 90.0, -45.0);
  check_arc(pts, {-1.0, 0.5}, 0.7, 90.0, -45.0);
  ASSERT_GE(pts.size(), 3U);
  for (std::size_t i = 1; i < pts.size(); ++i) EXPECT_LT(turn({-1.0, 0.5}, pts[i - 1], pts[i]), 0);
}

TEST(ScenarioLoader, TinyArcHasBothEndpoints) {
  const auto pts = arc_points(0.0, 0.0, 0.1, 0.0, 10.0);  // 1.7 cm: one segment
  check_arc(pts, {0.0, 0.0}, 0.1, 0.0, 10.0);
  EXPECT_EQ(pts.size(), 2U);
}

TEST(ScenarioLoader, ManyTurnArc) {
  check_arc(arc_points(0.0, 0.0, 2.0, 0.0, -3600.0), {0.0, 0.0}, 2.0, 0.0, -3600.0);
}

// ---- The repository's own scenarios ----

TEST(ScenarioLoader, EveryScenarioInTheRepositoryLoads) {
  const std::filesystem::path dir = CARRIL_SOURCE_DIR "/scenarios";
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
  int count = 0;
  for (auto it = std::filesystem::recursive_directory_iterator(dir);
       it != std::filesystem::recursive_directory_iterator(); ++it) {
    const auto& entry = *it;
    // scenarios/maps holds occupancy maps (loader_occupancy_map_test loads them), and
    // scenarios/campaigns campaign files (campaign_file_test): no scenarios.
    if (entry.is_directory() &&
        (entry.path() == dir / "maps" || entry.path() == dir / "campaigns")) {
      it.disable_recursion_pending();
    }
    if (!entry.is_regular_file() || entry.path().extension() != ".yaml") continue;
    ++count;
    const LoadResult r = load_scenario(entry.path().string(), test::robots_dir());
    EXPECT_TRUE(r.ok) << r.error;
  }
  std::cout << "[          ] " << count << " scenario file(s) under " << dir << "\n";
}

}  // namespace
}  // namespace carril::sim
