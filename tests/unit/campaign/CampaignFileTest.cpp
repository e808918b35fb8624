// Campaign files: a valid file loads; every kind of bad input is one error naming the file, the
// key and what was expected.
#include "host_sim/campaign/CampaignFile.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace carril::sim::campaign {
namespace {

const std::string kFile = std::string(CARRIL_SOURCE_DIR) + "/scenarios/campaigns/test.yaml";

std::string valid(const std::string& perturbations = "") {
  return "name: t\n"
         "seed: 3\n"
         "scenarios: [../circle.yaml, ../corners.yaml]\n"
         "robots:\n"
         "  - {preset: campero, strategy: marks}\n"
         "  - {preset: pioneer3at, strategy: pid}\n"
         "variants: 5\n" +
         (perturbations.empty()
              ? std::string("perturbations:\n  wheel_slip: {uniform: [0, 0.05]}\n")
              : "perturbations:\n" + perturbations);
}

std::string error_of(const std::string& text) {
  const CampaignLoad r = load_campaign_text(text, kFile);
  EXPECT_FALSE(r.ok) << text;
  return r.error;
}

TEST(CampaignFileTest, AValidFileLoads) {
  const CampaignLoad r =
      load_campaign_text(valid("  start_heading_deg: {normal: [0, 3], clip: [-8, 8]}\n"
                               "  wheel_slip: {uniform: [0, 0.05]}\n"
                               "  start_offset_m: {fixed: 0.02}\n"),
                         kFile);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.spec.name, "t");
  EXPECT_EQ(r.spec.seed, 3u);
  ASSERT_EQ(r.spec.scenarios.size(), 2u);
  EXPECT_EQ(r.spec.scenarios[0], std::string(CARRIL_SOURCE_DIR) + "/scenarios/circle.yaml");
  ASSERT_EQ(r.spec.robots.size(), 2u);
  EXPECT_EQ(r.spec.robots[1].strategy, "pid");
  EXPECT_EQ(r.spec.variant_count(), 2u * 2u * 5u);
  // In the fixed order of perturbation_kinds(), not the file's.
  ASSERT_EQ(r.spec.perturbations.size(), 3u);
  EXPECT_EQ(r.spec.perturbations[0].key, "start_offset_m");
  EXPECT_EQ(r.spec.perturbations[1].key, "start_heading_deg");
  EXPECT_EQ(r.spec.perturbations[1].dist.kind, Distribution::Kind::Normal);
  EXPECT_DOUBLE_EQ(r.spec.perturbations[1].dist.clip_hi, 8.0);
  EXPECT_EQ(r.spec.perturbations[2].key, "wheel_slip");
}

TEST(CampaignFileTest, WithoutRobotsEachScenarioKeepsItsOwn) {
  const CampaignLoad r =
      load_campaign_text("name: t\nscenarios: [../circle.yaml]\nvariants: 4\n", kFile);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.spec.robots.empty());
  EXPECT_TRUE(r.spec.perturbations.empty());
  EXPECT_EQ(r.spec.variant_count(), 4u);
}

TEST(CampaignFileTest, AnUnknownKeyIsNamed) {
  const std::string e = error_of(valid() + "runs: 3\n");
  EXPECT_NE(e.find("test.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("runs"), std::string::npos) << e;
}

TEST(CampaignFileTest, AnUnknownPerturbationListsTheKnownOnes) {
  const std::string e = error_of(valid("  tape_wear: {uniform: [0, 1]}\n"));
  EXPECT_NE(e.find("tape_wear"), std::string::npos) << e;
  EXPECT_NE(e.find("wheel_slip"), std::string::npos) << e;
}

TEST(CampaignFileTest, ImpossibleDistributionsAreRejected) {
  // low above high
  std::string e = error_of(valid("  wheel_slip: {uniform: [0.05, 0.01]}\n"));
  EXPECT_NE(e.find("perturbations.wheel_slip.uniform"), std::string::npos) << e;
  EXPECT_NE(e.find("low <= high"), std::string::npos) << e;
  // outside what the scenario format accepts for the key (slip in [0, 0.5])
  e = error_of(valid("  wheel_slip: {uniform: [0, 0.6]}\n"));
  EXPECT_NE(e.find("[0, 0.5]"), std::string::npos) << e;
  e = error_of(valid("  camera_noise: {fixed: -1}\n"));
  EXPECT_NE(e.find("perturbations.camera_noise.fixed"), std::string::npos) << e;
  // a normal without a clip could reach any value
  e = error_of(valid("  start_heading_deg: {normal: [0, 3]}\n"));
  EXPECT_NE(e.find("clip"), std::string::npos) << e;
  // a negative standard deviation
  e = error_of(valid("  start_heading_deg: {normal: [0, -3], clip: [-5, 5]}\n"));
  EXPECT_NE(e.find("normal[1]"), std::string::npos) << e;
  // a clip that does not hold the mean
  e = error_of(valid("  start_heading_deg: {normal: [0, 3], clip: [1, 5]}\n"));
  EXPECT_NE(e.find("mean"), std::string::npos) << e;
  // two kinds at once, and none
  e = error_of(valid("  wheel_slip: {fixed: 0.1, uniform: [0, 0.2]}\n"));
  EXPECT_NE(e.find("exactly one of"), std::string::npos) << e;
  e = error_of(valid("  wheel_slip: {}\n"));
  EXPECT_NE(e.find("exactly one of"), std::string::npos) << e;
  // a clip on a uniform
  e = error_of(valid("  wheel_slip: {uniform: [0, 0.1], clip: [0, 0.1]}\n"));
  EXPECT_NE(e.find("clip"), std::string::npos) << e;
}

TEST(CampaignFileTest, BadScenariosRobotsAndCountsAreRejected) {
  std::string e = error_of("name: t\nscenarios: [../no_such.yaml]\nvariants: 1\n");
  EXPECT_NE(e.find("no_such.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("scenarios[0]"), std::string::npos) << e;
  e = error_of("name: t\nscenarios: []\nvariants: 1\n");
  EXPECT_NE(e.find("scenarios"), std::string::npos) << e;
  e = error_of("name: t\nscenarios: [../circle.yaml]\nvariants: 0\n");
  EXPECT_NE(e.find("variants"), std::string::npos) << e;
  e = error_of(
      "name: t\nscenarios: [../circle.yaml]\nvariants: 1\nrobots: [{preset: campero, strategy: "
      "fast}]\n");
  EXPECT_NE(e.find("robots[0].strategy"), std::string::npos) << e;
  e = error_of("name: t\nscenarios: [../circle.yaml, ../corners.yaml]\nvariants: 600000\n");
  EXPECT_NE(e.find("1200000"), std::string::npos) << e;
  e = error_of("name: bad name\nscenarios: [../circle.yaml]\nvariants: 1\n");
  EXPECT_NE(e.find("name"), std::string::npos) << e;
  e = error_of("name: t\nscenarios: [../circle.yaml]\nvariants: '3'\n");
  EXPECT_NE(e.find("variants"), std::string::npos) << e;
}

TEST(CampaignFileTest, AMissingFileIsNamed) {
  const CampaignLoad r = load_campaign("/nonexistent/campaign.yaml");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("/nonexistent/campaign.yaml"), std::string::npos) << r.error;
}

TEST(CampaignFileTest, EveryShippedCampaignLoads) {
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CARRIL_SOURCE_DIR) +
                                                           "/scenarios/campaigns")) {
    if (e.path().extension() != ".yaml") continue;
    ++count;
    const CampaignLoad r = load_campaign(e.path().string());
    EXPECT_TRUE(r.ok) << r.error;
  }
  EXPECT_GE(count, 3);
}

}  // namespace
}  // namespace carril::sim::campaign
