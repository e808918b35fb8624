// The height field at known points: ramps (with top, pair, one-way), platforms, pits, trenches,
// obstacle tops; overlaps take the highest; bounds; garbage input.
#include "host_sim/world/HeightField.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace carril::sim {
namespace {

double tan_deg(double d) {
  return std::tan(d * std::numbers::pi / 180.0);
}

TerrainSpec ramp(double cx, double angle, double len, double top, bool descend) {
  TerrainSpec t;
  t.type = TerrainType::Ramp;
  t.center = {cx, 0.0};
  t.angle_deg = angle;
  t.length_m = len;
  t.width_m = 2.0;
  t.top_m = top;
  t.descend = descend;
  return t;
}

TerrainSpec box(TerrainType type, Vec2 c, double len, double width, double h) {
  TerrainSpec t;
  t.type = type;
  t.center = c;
  t.length_m = len;
  t.width_m = width;
  if (type == TerrainType::Trench) {
    t.depth_m = h;
  } else {
    t.height_m = h;
  }
  return t;
}

TEST(HeightField, HillRisesAcrossTheTopAndComesDown) {
  // 5 deg over 2 m, 1 m top, down again: footprint 5 m, from x = -2.5 to 2.5.
  const HeightField f({ramp(0.0, 5.0, 2.0, 1.0, true)}, {});
  const double h = 2.0 * tan_deg(5.0);
  EXPECT_NEAR(f.ground_at(-2.5, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(f.ground_at(-1.5, 0.3), tan_deg(5.0), 1e-12);
  EXPECT_NEAR(f.ground_at(-0.5, 0.0), h, 1e-12);
  EXPECT_NEAR(f.ground_at(0.0, -0.9), h, 1e-12);
  EXPECT_NEAR(f.ground_at(1.5, 0.0), tan_deg(5.0), 1e-12);
  EXPECT_EQ(f.ground_at(2.6, 0.0), 0.0);   // beyond its end
  EXPECT_EQ(f.ground_at(-1.5, 1.1), 0.0);  // beside it: its long sides are vertical edges
  const GroundSample up = f.ground_sample(-1.5, 0.0);
  EXPECT_NEAR(up.dzdx, tan_deg(5.0), 1e-12);
  EXPECT_NEAR(up.dzdy, 0.0, 1e-12);
  EXPECT_NEAR(f.ground_sample(1.5, 0.0).dzdx, -tan_deg(5.0), 1e-12);
  EXPECT_NEAR(f.ground_sample(0.0, 0.0).dzdx, 0.0, 1e-12);
  EXPECT_NEAR(f.max_height(), h, 1e-12);
  EXPECT_EQ(f.min_height(), 0.0);
}

TEST(HeightField, RampPairAndOneWayRamp) {
  TerrainSpec pair = ramp(0.0, 5.0, 1.0, 0.0, false);
  pair.angle2_deg = 11.0;
  pair.length2_m = 1.0;  // footprint 2 m: x = -1 .. 1
  const HeightField f({pair}, {});
  EXPECT_NEAR(f.ground_at(-0.5, 0.0), 0.5 * tan_deg(5.0), 1e-12);
  EXPECT_NEAR(f.ground_at(0.5, 0.0), tan_deg(5.0) + 0.5 * tan_deg(11.0), 1e-12);
  EXPECT_NEAR(f.ground_sample(0.5, 0.0).dzdx, tan_deg(11.0), 1e-12);
  // No descent: the top end is a drop to the floor.
  EXPECT_NEAR(f.ground_at(0.999, 0.0), tan_deg(5.0) + 0.999 * tan_deg(11.0), 1e-9);
  EXPECT_EQ(f.ground_at(1.001, 0.0), 0.0);
}

TEST(HeightField, TurnedRampRisesAlongItsOwnX) {
  TerrainSpec t = ramp(0.0, 10.0, 2.0, 0.0, false);  // x = -1 .. 1 before turning
  t.yaw_rad = std::numbers::pi / 2;                  // now rises toward +y
  const HeightField f({t}, {});
  EXPECT_NEAR(f.ground_at(0.0, 0.5), 1.5 * tan_deg(10.0), 1e-12);
  const GroundSample g = f.ground_sample(0.5, 0.0);
  EXPECT_NEAR(g.dzdx, 0.0, 1e-12);
  EXPECT_NEAR(g.dzdy, tan_deg(10.0), 1e-12);
}

TEST(HeightField, PlatformPitTrenchAndOverlaps) {
  const HeightField f({box(TerrainType::Step, {0, 0}, 2.0, 2.0, 0.2),
                       box(TerrainType::Step, {5, 0}, 1.0, 1.0, -0.15),
                       box(TerrainType::Trench, {10, 0}, 4.0, 0.5, 0.3),
                       // A lower platform overlapping the first: the highest wins.
                       box(TerrainType::Step, {1, 0}, 2.0, 1.0, 0.05)},
                      {});
  EXPECT_EQ(f.ground_at(0.0, 0.0), 0.2);
  EXPECT_EQ(f.ground_at(0.5, 0.0), 0.2);   // on both: the higher
  EXPECT_EQ(f.ground_at(1.5, 0.0), 0.05);  // on the lower one only
  EXPECT_EQ(f.ground_at(2.1, 0.0), 0.0);
  EXPECT_EQ(f.ground_at(5.0, 0.4), -0.15);
  EXPECT_EQ(f.ground_at(5.0, 0.6), 0.0);
  EXPECT_EQ(f.ground_at(11.9, -0.2), -0.3);
  EXPECT_EQ(f.ground_at(10.0, 0.3), 0.0);
  EXPECT_EQ(f.max_height(), 0.2);
  EXPECT_EQ(f.min_height(), -0.3);
}

TEST(HeightField, ObstacleTopsStandOnTheGround) {
  ObstacleSpec cube;  // 1 x 1 x 1 m by default
  cube.center = {5.0, 5.0};
  ObstacleSpec post;
  post.shape = ObstacleShape::Cylinder;
  post.center = {0.5, 0.0};
  post.radius_m = 0.2;
  post.height_m = 0.5;
  const HeightField f({box(TerrainType::Step, {0, 0}, 2.0, 2.0, 0.2)}, {cube, post});
  EXPECT_EQ(f.height_at(5.4, 5.4), 1.0);
  EXPECT_EQ(f.ground_at(5.4, 5.4), 0.0);  // the ground alone has no obstacles
  EXPECT_EQ(f.height_at(5.6, 5.0), 0.0);
  EXPECT_NEAR(f.height_at(0.6, 0.1), 0.7, 1e-12);  // on the 0.2 m platform
  EXPECT_EQ(f.height_at(0.0, 0.0), 0.2);
  EXPECT_EQ(f.max_height(), 1.0);
}

TEST(HeightField, NonFiniteQueriesGiveTheFloorWithoutTrapping) {
  const HeightField f({box(TerrainType::Step, {0, 0}, 2.0, 2.0, 0.2)}, {ObstacleSpec{}});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(f.height_at(nan, 0.0), 0.0);
  EXPECT_EQ(f.height_at(0.0, inf), 0.0);
  EXPECT_EQ(f.ground_sample(-inf, nan).z_m, 0.0);
}

}  // namespace
}  // namespace carril::sim
