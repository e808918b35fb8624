// Variants: reproducible from (campaign, index) alone, different across indices and seeds, draws
// within their distributions, and scenario files the simulator's strict loader accepts with the
// perturbations applied.
#include "host_sim/campaign/Variant.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <string>

#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim::campaign {
namespace {

const std::string kSrc = CARRIL_SOURCE_DIR;
const std::string kFile = kSrc + "/scenarios/campaigns/test.yaml";
const std::string kRobots = kSrc + "/config/robots";

CampaignSpec spec_of(const std::string& text) {
  const CampaignLoad r = load_campaign_text(text, kFile);
  EXPECT_TRUE(r.ok) << r.error;
  return r.spec;
}

const std::string kCampaign =
    "name: t\nseed: 11\nscenarios: [../circle.yaml, ../corners.yaml]\n"
    "robots: [{preset: campero, strategy: marks}, {preset: pioneer3at, strategy: pid}]\n"
    "variants: 3\n"
    "perturbations:\n"
    "  start_offset_m: {uniform: [-0.05, 0.05]}\n"
    "  start_heading_deg: {normal: [0, 4], clip: [-6, 6]}\n"
    "  camera_noise: {uniform: [0, 8]}\n"
    "  wheel_slip: {uniform: [0, 0.05]}\n"
    "  wheel_radius_error: {fixed: -0.01}\n"
    "  obstacle_jitter_m: {fixed: 0.1}\n";

TEST(VariantTest, IndicesWalkScenariosThenRobotsThenVariants) {
  const CampaignSpec s = spec_of(kCampaign);
  ASSERT_EQ(s.variant_count(), 12u);
  EXPECT_EQ(make_variant(s, 0).base_name, "circle");
  EXPECT_EQ(make_variant(s, 0).preset, "campero");
  EXPECT_EQ(make_variant(s, 3).preset, "pioneer3at");
  EXPECT_EQ(make_variant(s, 3).strategy, "pid");
  EXPECT_EQ(make_variant(s, 6).base_name, "corners");
  EXPECT_EQ(make_variant(s, 11).preset, "pioneer3at");
}

// yaml-cpp 0.7 reads the quote on to the end of the file: the variant would lose its expect
// block and pass. The base is pre-checked as every loader's file is.
TEST(VariantTest, ABaseWithAnUnterminatedQuoteIsRefusedNotSwallowed) {
  CampaignSpec s = spec_of(kCampaign);
  const std::string bad = ::testing::TempDir() + "/quote_base.yaml";
  std::ofstream(bad) << "name: \"circle\nexpect: {result: end_reached}\n";
  s.scenarios[0] = bad;
  const ScenarioText t = variant_scenario(s, make_variant(s, 0));
  EXPECT_FALSE(t.ok);
  EXPECT_EQ(t.error.rfind(bad + ":1: invalid YAML: the double quote at column 7", 0), 0U)
      << t.error;
}

TEST(VariantTest, TheSameIndexGivesTheSameScenarioAndAnotherDiffers) {
  const CampaignSpec s = spec_of(kCampaign);
  const ScenarioText a = variant_scenario(s, make_variant(s, 4));
  const ScenarioText b = variant_scenario(spec_of(kCampaign), make_variant(s, 4));
  ASSERT_TRUE(a.ok) << a.error;
  EXPECT_EQ(a.text, b.text);
  const ScenarioText c = variant_scenario(s, make_variant(s, 5));
  EXPECT_NE(a.text, c.text);
  CampaignSpec reseeded = s;
  reseeded.seed = 12;
  EXPECT_NE(variant_scenario(reseeded, make_variant(reseeded, 4)).text, a.text);
  EXPECT_NE(make_variant(reseeded, 4).seed, make_variant(s, 4).seed);
  EXPECT_NE(make_variant(reseeded, 4).values, make_variant(s, 4).values);
  std::set<std::uint64_t> seeds;
  for (std::uint64_t i = 0; i < s.variant_count(); ++i) seeds.insert(make_variant(s, i).seed);
  EXPECT_EQ(seeds.size(), s.variant_count());
}

TEST(VariantTest, DrawsStayInTheirDistributions) {
  CampaignSpec s = spec_of(kCampaign);
  s.variants = 2000;
  s.scenarios.resize(1);
  s.robots.resize(1);
  double sum_slip = 0.0, sum_heading = 0.0, sum_sq_heading = 0.0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const Variant v = make_variant(s, i);
    ASSERT_EQ(v.values.size(), 6u);
    EXPECT_GE(v.values[0], -0.05);
    EXPECT_LE(v.values[0], 0.05);
    EXPECT_GE(v.values[1], -6.0);
    EXPECT_LE(v.values[1], 6.0);
    EXPECT_GE(v.values[3], 0.0);
    EXPECT_LE(v.values[3], 0.05);
    EXPECT_EQ(v.values[4], -0.01);
    sum_slip += v.values[3];
    sum_heading += v.values[1];
    sum_sq_heading += v.values[1] * v.values[1];
  }
  // Means and spread of 2000 draws: uniform [0, 0.05] has mean 0.025 (standard error 0.0003); a
  // normal (0, 4) clipped at 1.5 sigma has mean 0 and a standard deviation of about 3.0.
  EXPECT_NEAR(sum_slip / 2000.0, 0.025, 0.0015);
  EXPECT_NEAR(sum_heading / 2000.0, 0.0, 0.3);
  EXPECT_NEAR(std::sqrt(sum_sq_heading / 2000.0), 3.0, 0.3);
}

TEST(VariantTest, AddingAPerturbationLeavesTheOthersValues) {
  const CampaignSpec s = spec_of(kCampaign);
  const CampaignSpec fewer = spec_of(
      "name: t\nseed: 11\nscenarios: [../circle.yaml, ../corners.yaml]\n"
      "robots: [{preset: campero, strategy: marks}, {preset: pioneer3at, strategy: pid}]\n"
      "variants: 3\nperturbations:\n  wheel_slip: {uniform: [0, 0.05]}\n");
  for (std::uint64_t i = 0; i < s.variant_count(); ++i) {
    EXPECT_EQ(make_variant(s, i).values[3], make_variant(fewer, i).values[0]);
    EXPECT_EQ(make_variant(s, i).seed, make_variant(fewer, i).seed);
  }
}

TEST(VariantTest, TheScenarioLoadsStrictlyWithThePerturbationsApplied) {
  const CampaignSpec s = spec_of(kCampaign);
  for (std::uint64_t i : {0u, 4u, 7u, 11u}) {
    const Variant v = make_variant(s, i);
    const ScenarioText t = variant_scenario(s, v);
    ASSERT_TRUE(t.ok) << t.error;
    const LoadResult r = load_scenario_text(t.text, "variant.yaml", kRobots);
    ASSERT_TRUE(r.ok) << r.error << "\n" << t.text;
    const Scenario& sc = r.scenario;
    EXPECT_EQ(sc.seed, v.seed);
    EXPECT_EQ(sc.robot.preset, v.preset);
    EXPECT_EQ(sc.mission.strategy, v.strategy);
    const LoadResult base = load_scenario(s.scenarios[v.scenario], kRobots);
    ASSERT_TRUE(base.ok) << base.error;
    // Sideways by the offset (both courses start heading along +x), turned by the heading draw.
    const auto& p0 = base.scenario.robot.start;
    EXPECT_NEAR(sc.robot.start.x - p0.x, 0.0, 1e-6);
    EXPECT_NEAR(sc.robot.start.y - p0.y, v.values[0], 2e-6);
    EXPECT_NEAR((sc.robot.start.yaw_rad - p0.yaw_rad) * 180.0 / M_PI, v.values[1], 1e-5);
    EXPECT_NEAR(sc.robot.camera.noise_std, v.values[2], 1e-6);
    EXPECT_NEAR(sc.odometry.slip, v.values[3], 1e-6);
    EXPECT_NEAR(sc.odometry.wheel_radius_error, -0.01, 1e-9);
    ASSERT_EQ(sc.obstacles.size(), base.scenario.obstacles.size());
    for (std::size_t k = 0; k < sc.obstacles.size(); ++k) {
      const double dx = sc.obstacles[k].center.x - base.scenario.obstacles[k].center.x;
      const double dy = sc.obstacles[k].center.y - base.scenario.obstacles[k].center.y;
      EXPECT_LE(std::hypot(dx, dy), 0.1 + 1e-6);
    }
  }
}

TEST(VariantTest, AMapPathBecomesAbsolute) {
  const CampaignSpec s = spec_of("name: t\nscenarios: [../goto_house_mcl.yaml]\nvariants: 1\n");
  const ScenarioText t = variant_scenario(s, make_variant(s, 0));
  ASSERT_TRUE(t.ok) << t.error;
  EXPECT_NE(t.text.find("map: " + kSrc + "/scenarios/maps/house.yaml"), std::string::npos)
      << t.text;
  const LoadResult r = load_scenario_text(t.text, "/tmp/elsewhere/variant.yaml", kRobots);
  EXPECT_TRUE(r.ok) << r.error;
}

TEST(VariantTest, TheSensorAndFloorPerturbationsLoadStrictly) {
  const CampaignSpec s = spec_of(
      "name: t\nseed: 2\nscenarios: [../corners.yaml]\nvariants: 6\n"
      "perturbations:\n"
      "  tape_gaps_per_m: {uniform: [0, 0.5]}\n"
      "  tape_gap_length_m: {fixed: 0.12}\n"
      "  tape_fade: {uniform: [0, 0.4]}\n"
      "  floor_brightness: {uniform: [0.7, 1.3]}\n"
      "  camera_exposure: {uniform: [0.8, 1.2]}\n"
      "  glare_intensity: {uniform: [0, 80]}\n"
      "  lidar_dropout: {uniform: [0, 0.1]}\n"
      "  extra_obstacles: {fixed: 3}\n");
  const LoadResult base = load_scenario(s.scenarios[0], kRobots);
  ASSERT_TRUE(base.ok) << base.error;
  for (std::uint64_t i = 0; i < s.variant_count(); ++i) {
    const Variant v = make_variant(s, i);
    const ScenarioText t = variant_scenario(s, v);
    ASSERT_TRUE(t.ok) << t.error;
    const LoadResult r = load_scenario_text(t.text, "variant.yaml", kRobots);
    ASSERT_TRUE(r.ok) << r.error << "\n" << t.text;
    const Scenario& sc = r.scenario;
    // extra_obstacles comes first in perturbation_kinds() after the jitter.
    EXPECT_NEAR(sc.tape_wear.gaps_per_m, v.values[1], 1e-6);
    EXPECT_NEAR(sc.tape_wear.gap_length_m, 0.12, 1e-9);
    EXPECT_NEAR(sc.tape_wear.fade, v.values[3], 1e-6);
    EXPECT_NEAR(double(sc.floor.r), std::round(90.0 * v.values[4]), 0.5);
    EXPECT_NEAR(sc.robot.camera.exposure, v.values[5], 1e-6);
    EXPECT_NEAR(sc.glare.intensity, v.values[6], 1e-6);
    EXPECT_NEAR(sc.robot.lidar.dropout, v.values[7], 1e-6);
    // Three more cylinders, off the tape and away from the start.
    ASSERT_EQ(sc.obstacles.size(), base.scenario.obstacles.size() + 3);
    for (std::size_t k = base.scenario.obstacles.size(); k < sc.obstacles.size(); ++k) {
      const ObstacleSpec& o = sc.obstacles[k];
      EXPECT_EQ(o.shape, ObstacleShape::Cylinder);
      double d = 1e9;
      const auto& pts = sc.lines[0].points;
      for (std::size_t j = 0; j + 1 < pts.size(); ++j) {
        const double dx = pts[j + 1].x - pts[j].x, dy = pts[j + 1].y - pts[j].y;
        const double t = std::clamp(
            ((o.center.x - pts[j].x) * dx + (o.center.y - pts[j].y) * dy) / (dx * dx + dy * dy),
            0.0, 1.0);
        d = std::min(d, std::hypot(o.center.x - pts[j].x - t * dx, o.center.y - pts[j].y - t * dy));
      }
      EXPECT_GE(d, o.radius_m + 0.5 - 1e-6);
      EXPECT_GE(std::hypot(o.center.x - sc.robot.start.x, o.center.y - sc.robot.start.y),
                o.radius_m + 1.0 - 1e-6);
    }
  }
}

}  // namespace
}  // namespace carril::sim::campaign
