// AliasSearch: a scan that fits as well elsewhere on the map (two alike rooms, a room alike when
// turned half round) makes its pose ambiguous and names the other pose; a scan that fits only
// where it was taken does not; the result does not depend on how the work is spread.
#include "firmware/estimation/AliasSearch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "firmware/estimation/LikelihoodField.hpp"
#include "tests/unit/estimation/MclWorld.hpp"

namespace carril::fw {
namespace {

using test::mcl::fill;
using test::mcl::ScanSpec;
using test::mcl::synth_scan;

const Pose2 kMount{0.1, 0.0, 0.0};
constexpr int kNx = 200, kNy = 80;  // 10 x 4 m at 0.05 m

// kNx x kNy cells at 0.05 m, origin (0, 0).
OccupancyGrid grid(const std::vector<std::uint8_t>& c) {
  OccupancyGrid g(c.size());
  MapInfo info;
  info.nx = kNx;
  info.ny = kNy;
  info.resolution_m = 0.05;
  EXPECT_TRUE(g.assign(info, c.data()).is_ok());
  return g;
}

// Two 4 x 3 m rooms side by side (x 0.5..4.5 and 5.5..9.5, y 0.5..3.5), walls between, a box in
// each at the same place in the room; unless `alike`, the east room is 0.6 m shallower (y up to
// 2.9) and its box elsewhere. With `pillar`, a pillar in the west room's north-east corner only.
OccupancyGrid rooms(bool alike, bool pillar) {
  std::vector<std::uint8_t> c(std::size_t(kNx * kNy), cost::kLethal);
  const auto free = [&](double x0, double y0, double x1, double y1) {
    fill(c, kNx, kNy, x0, y0, x1, y1, cost::kFree);
  };
  const auto wall = [&](double x0, double y0, double x1, double y1) {
    fill(c, kNx, kNy, x0, y0, x1, y1, cost::kLethal);
  };
  free(0.5, 0.5, 4.5, 3.5);
  free(5.5, 0.5, 9.5, alike ? 3.5 : 2.9);
  wall(1.0, 1.0, 1.5, 1.4);
  if (alike) {
    wall(6.0, 1.0, 6.5, 1.4);
  } else {
    wall(8.0, 2.0, 8.5, 2.4);
  }
  if (pillar) wall(3.9, 2.9, 4.5, 3.5);
  return grid(c);
}

// One 4 x 3 m room (x 0.5..4.5, y 0.5..3.5) with boxes in opposite corners: the same turned half
// round about its centre (2.5, 2.0), and alike under no shift or mirror.
OccupancyGrid turned_room() {
  std::vector<std::uint8_t> c(std::size_t(kNx * kNy), cost::kLethal);
  fill(c, kNx, kNy, 0.5, 0.5, 4.5, 3.5, cost::kFree);
  fill(c, kNx, kNy, 0.5, 0.5, 1.2, 0.9, cost::kLethal);
  fill(c, kNx, kNy, 3.8, 3.1, 4.5, 3.5, cost::kLethal);
  return grid(c);
}

struct AliasWorld {
  OccupancyGrid map;
  LikelihoodField field;
  hal::LaserScan scan;
  AliasWorld(OccupancyGrid m, const Pose2& truth, std::uint64_t seed = 1)
      : map(std::move(m)), field(field_config(), map) {
    MclRng rng(seed);
    ScanSpec spec;
    spec.dropout = 0.0;
    spec.clutter = 0.0;
    synth_scan(map, truth, kMount, spec, rng, scan);
  }
  static LikelihoodFieldConfig field_config() {
    LikelihoodFieldConfig f;
    f.sigma_hit_m = 0.1;
    f.z_max_m = 10.0;
    // Depth inside a wall counts (as the simulator's configuration has it): these maps are solid
    // outside their rooms, and to occupied cells' centres every endpoint in the solid would fit.
    f.surface_distance = true;
    return f;
  }
};

AliasSearchConfig config(int headings = 4) {
  AliasSearchConfig c;
  c.headings = headings;
  c.max_range_m = 10.0;
  return c;
}

AliasResult run(AliasSearch& s, const hal::LaserScan& scan, const Pose2& pose, long lookups) {
  EXPECT_TRUE(s.begin(scan, pose, kMount));
  int steps = 0;
  while (s.step(lookups)) ++steps;
  EXPECT_FALSE(s.busy());
  return s.result();
}

TEST(AliasSearch, AlikeRoomsMakeThePoseAmbiguousAndNameTheOtherRoom) {
  const Pose2 truth{2.5, 2.2, 0.4};
  const AliasWorld w(rooms(true, false), truth);
  AliasSearch s(config(), w.field, w.map);
  ASSERT_TRUE(s.status().is_ok());
  const AliasResult r = run(s, w.scan, truth, 1000000);
  EXPECT_TRUE(r.ambiguous) << "own " << r.own_fit << " alias " << r.alias_fit;
  EXPECT_NEAR(r.alias.x, truth.x + 5.0, 0.1);
  EXPECT_NEAR(r.alias.y, truth.y, 0.1);
  EXPECT_NEAR(wrap_angle(r.alias.yaw - truth.yaw), 0.0, 0.05);
  EXPECT_NEAR(r.pose.x, truth.x, 0.1);
  EXPECT_NEAR(r.pose.y, truth.y, 0.1);
  // Asked from the other room, the first one is the alias.
  const Pose2 other{truth.x + 5.0, truth.y, truth.yaw};
  const AliasResult back = run(s, w.scan, other, 1000000);
  EXPECT_TRUE(back.ambiguous);
  EXPECT_NEAR(back.alias.x, truth.x, 0.1);
}

TEST(AliasSearch, ARoomThatDiffersIsNoAlias) {
  const Pose2 truth{2.5, 2.2, 0.4};
  const AliasWorld w(rooms(false, false), truth);
  AliasSearch s(config(), w.field, w.map);
  const AliasResult r = run(s, w.scan, truth, 1000000);
  EXPECT_FALSE(r.ambiguous) << "own " << r.own_fit << " alias " << r.alias_fit << " at "
                            << r.alias.x << " " << r.alias.y << " " << r.alias.yaw;
  EXPECT_GT(r.own_fit, r.alias_fit + config().margin);
  EXPECT_GT(s.candidate_count(), 1000);
}

TEST(AliasSearch, AWrongPoseFitsWorseThanTheAliasItNames) {
  // The filter converged in the east room, the robot stands in the west one, which differs: the
  // search names the truth as the better pose.
  const Pose2 truth{2.5, 2.2, 0.4};
  const AliasWorld w(rooms(false, false), truth);
  AliasSearch s(config(), w.field, w.map);
  const AliasResult r = run(s, w.scan, {truth.x + 5.0, truth.y, truth.yaw}, 1000000);
  EXPECT_TRUE(r.ambiguous);
  EXPECT_GT(r.alias_fit, r.own_fit + 0.1);
  EXPECT_NEAR(r.alias.x, truth.x, 0.1);
  EXPECT_NEAR(r.alias.y, truth.y, 0.1);
}

TEST(AliasSearch, ARoomAlikeTurnedHalfRoundIsFoundOnlyWithTheTurnedHeadings) {
  const Pose2 truth{1.6, 2.3, 0.3};
  const AliasWorld w(turned_room(), truth);
  // The same pose turned half round about the room's centre (2.5, 2.0).
  const Pose2 turned{5.0 - truth.x, 4.0 - truth.y, wrap_angle(truth.yaw + kPi)};
  AliasSearch four(config(4), w.field, w.map);
  const AliasResult r = run(four, w.scan, truth, 1000000);
  EXPECT_TRUE(r.ambiguous) << "own " << r.own_fit << " alias " << r.alias_fit;
  EXPECT_NEAR(r.alias.x, turned.x, 0.1);
  EXPECT_NEAR(r.alias.y, turned.y, 0.1);
  EXPECT_NEAR(wrap_angle(r.alias.yaw - turned.yaw), 0.0, 0.05);
  AliasSearch one(config(1), w.field, w.map);
  const AliasResult r1 = run(one, w.scan, truth, 1000000);
  EXPECT_FALSE(r1.ambiguous) << "own " << r1.own_fit << " alias " << r1.alias_fit;
}

TEST(AliasSearch, TheResultDoesNotDependOnTheStepBudget) {
  const Pose2 truth{2.5, 2.2, 0.4};
  const AliasWorld w(rooms(true, true), truth);
  AliasSearch s(config(), w.field, w.map);
  const AliasResult whole = run(s, w.scan, truth, 100000000);
  for (long budget : {1L, 700L, 20000L}) {
    const AliasResult r = run(s, w.scan, truth, budget);
    EXPECT_EQ(r.own_fit, whole.own_fit) << budget;
    EXPECT_EQ(r.alias_fit, whole.alias_fit) << budget;
    EXPECT_EQ(r.alias.x, whole.alias.x) << budget;
    EXPECT_EQ(r.alias.y, whole.alias.y) << budget;
    EXPECT_EQ(r.ambiguous, whole.ambiguous) << budget;
  }
  // A budget of one lookup still makes progress: at least a candidate (or a refinement) a step.
  EXPECT_TRUE(s.begin(w.scan, truth, kMount));
  int steps = 1;
  while (s.step(1)) ++steps;
  EXPECT_LE(steps, 4 * s.candidate_count() + 2 * AliasSearch::kKeep + 1);
  EXPECT_EQ(s.completed(), 5U);
}

TEST(AliasSearch, ScanWithoutValidReturnsIsRefusedAndAbortStops) {
  const Pose2 truth{2.5, 2.2, 0.4};
  AliasWorld w(rooms(true, false), truth);
  AliasSearch s(config(), w.field, w.map);
  hal::LaserScan empty = w.scan;
  for (std::size_t k = 0; k < empty.count; ++k) empty.ranges_m[k] = 0.0F;  // below range_min
  EXPECT_FALSE(s.begin(empty, truth, kMount));
  EXPECT_FALSE(s.busy());
  ASSERT_TRUE(s.begin(w.scan, truth, kMount));
  EXPECT_TRUE(s.step(10));
  s.abort();
  EXPECT_FALSE(s.busy());
  EXPECT_EQ(s.completed(), 0U);
}

TEST(AliasSearch, ConfigErrorsNameTheField) {
  const AliasWorld w(rooms(true, false), {2.5, 2.2, 0.4});
  AliasSearchConfig c = config();
  c.headings = 0;
  AliasSearch bad(c, w.field, w.map);
  ASSERT_FALSE(bad.status().is_ok());
  EXPECT_NE(std::string(bad.status().message()).find("localisation.alias.headings"),
            std::string::npos)
      << bad.status().message();
  EXPECT_FALSE(bad.begin(w.scan, {2.5, 2.2, 0.4}, kMount));
  c = config();
  c.stride_m = 0.0;
  EXPECT_FALSE(AliasSearchConfig(c).validate().is_ok());
}

}  // namespace
}  // namespace carril::fw
