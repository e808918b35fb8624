// BodyGuard: the lethal cells round a rectangular body and the checks on them. A square body
// 0.5 x 0.5 m padded 5 cm, on a 5 cm grid; single lethal cells placed round it.
#include "firmware/mission/BodyGuard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {
namespace {

struct Grid {
  Grid() {
    g.init(80, 80, 0.05, cost::kFree);
    g.move_origin(-40, -40);  // (-2, -2) to (2, 2) m
  }
  // The cell whose centre is nearest (x, y) [m] made lethal.
  void lethal(double x, double y) { g.at(g.cell_of(x), g.cell_of(y)) = cost::kLethal; }
  RollingGrid<std::uint8_t> g;
};

BodyGuard square() {
  return BodyGuard(0.25, 0.25, 0.05, 1.2);
}

TEST(BodyGuardTest, NothingAroundIsClearEverywhere) {
  Grid m;
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  EXPECT_EQ(b.cells(), 0u);
  EXPECT_FALSE(b.nearest().found);
  EXPECT_DOUBLE_EQ(b.free_length(0.0, false, 0.7), 0.7);
  EXPECT_TRUE(b.rotation_clear(3.0));
  EXPECT_NEAR(b.swept_radius(), std::hypot(0.25, 0.25) + 0.075, 1e-9);
}

// A cell beside the body, between its inscribed and its swept circle: no line across the front
// sees it, driving on along it is free, but turning either way swings a corner into it.
TEST(BodyGuardTest, ACellInsideTheSweptCircleBlocksTheTurnNotTheDrive) {
  Grid m;
  m.lethal(0.025, 0.325);  // 7.5 cm off the left side, 0.33 m from the centre
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  ASSERT_EQ(b.cells(), 1u);
  EXPECT_NEAR(b.nearest().d_m, std::hypot(0.025, 0.325), 1e-6);
  EXPECT_LT(b.nearest().d_m, b.swept_radius());
  // The front corner meets it after 0.5 rad to the left, the rear one after 0.65 to the right.
  EXPECT_TRUE(b.rotation_clear(0.4));
  EXPECT_FALSE(b.rotation_clear(0.8));
  EXPECT_FALSE(b.rotation_clear(-0.8));
  EXPECT_DOUBLE_EQ(b.free_length(0.0, false, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(b.free_length(0.0, true, 0.5), 0.5);
  // Beside the middle of the side, no arc runs into it (its inner side turns inside it).
  EXPECT_DOUBLE_EQ(b.free_length(1.0, false, 0.5), 0.5);
  // Backed off by 0.4 m, the cell lies outside the swept circle: the turn is clear.
  b.gather(Pose2{-0.4, 0.0, 0.0}, m.g);
  EXPECT_GT(b.nearest().d_m, b.swept_radius());
  EXPECT_TRUE(b.rotation_clear(kPi));
}

// A row of cells along the left side, from 0.2 m behind the centre to 0.6 m ahead, blocks a turn
// here; escape_shift finds the nearest place,
// straight back or ahead, from which the turn is clear and the way there is free.
TEST(BodyGuardTest, EscapeShiftFindsTheNearestPlaceTheTurnIsClearFrom) {
  Grid m;
  // 12.5 cm off the left side: inside the swept circle, outside the padded side.
  for (double x = -0.2; x <= 0.6; x += 0.05) m.lethal(x, 0.375);
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  ASSERT_FALSE(b.rotation_clear(kPi));
  const double back = b.escape_shift(kPi, 0.05, 1.0, 0.0);
  ASSERT_LT(back, 0.0);  // the row ends nearer behind than ahead
  EXPECT_TRUE(b.rotation_clear(kPi, back));
  EXPECT_FALSE(b.rotation_clear(kPi, back + 0.05));  // the nearest such place
  // A cell just behind the body: backing is not free, so the way ahead past the row's end.
  m.lethal(-0.35, 0.0);
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  const double ahead = b.escape_shift(kPi, 0.05, 1.2, 0.0);
  EXPECT_GT(ahead, 0.0);
  EXPECT_TRUE(b.rotation_clear(kPi, ahead));
  EXPECT_FALSE(b.rotation_clear(kPi, ahead - 0.05));
  // Nowhere within 0.3 m: none.
  EXPECT_EQ(b.escape_shift(kPi, 0.05, 0.3, 0.0), 0.0);
  // The way must also be free for min_free_m: with a cell 0.9 m behind (about 0.55 m of room),
  // backing serves a caller that needs no room, not one that needs 0.6 m.
  Grid m2;
  for (double x = -0.2; x <= 0.6; x += 0.05) m2.lethal(x, 0.375);
  m2.lethal(-0.9, 0.0);
  b.gather(Pose2{0.0, 0.0, 0.0}, m2.g);
  EXPECT_LT(b.escape_shift(kPi, 0.05, 1.2, 0.0), 0.0);
  EXPECT_GT(b.escape_shift(kPi, 0.05, 1.2, 0.6), 0.0);
}

// A cell straight ahead: the free length is what is left between it and the padded front.
TEST(BodyGuardTest, FreeLengthStopsShortOfACellAhead) {
  Grid m;
  m.lethal(1.025, 0.025);
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.025, 0.0}, m.g);
  // Front 0.25, padding 0.05, half a cell 0.025: the cell's centre is met at 1.025 - 0.325.
  const double free = b.free_length(0.0, false, 2.0);
  EXPECT_LE(free, 0.70);
  EXPECT_GE(free, 0.68);
  EXPECT_DOUBLE_EQ(b.free_length(0.0, true, 0.5), 0.5);  // nothing behind
  const BodyGuard::Corridor c = b.corridor(Vec2(1.0, 0.0), 0.3, 2.0, 0.3);
  EXPECT_NEAR(c.first_m, 1.025, 1e-6);
  EXPECT_EQ(c.cells, 1u);
  EXPECT_NEAR(c.mean_side_m, 0.0, 1e-6);
  EXPECT_DOUBLE_EQ(b.corridor(Vec2(0.0, 1.0), 0.3, 2.0).first_m, 2.0);  // not to the left
}

// A cell ahead on the left, clear of the straight path: an arc to the left (1 m radius) runs
// into it, one to the right does not.
TEST(BodyGuardTest, AnArcIsCheckedAlongItsSweep) {
  Grid m;
  m.lethal(0.625, 0.375);
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  EXPECT_DOUBLE_EQ(b.free_length(0.0, false, 0.6), 0.6);
  const double left = b.free_length(1.0, false, 0.6);
  EXPECT_GT(left, 0.05);
  EXPECT_LT(left, 0.5);
  EXPECT_DOUBLE_EQ(b.free_length(-1.0, false, 0.6), 0.6);
  EXPECT_DOUBLE_EQ(b.free_length(1.0, true, 0.6), 0.6);  // backward: away from it
}

// Cells already inside the padding (5 cm off the side): moving along them stays allowed; only
// the bare body (and half a cell) is kept off them.
TEST(BodyGuardTest, ACellInThePaddingStopsOnlyTheBody) {
  Grid m;
  m.lethal(0.025, 0.325);
  m.lethal(-0.025, 0.325);
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.025, 0.0}, m.g);  // the cells 0.30 m left of the centre
  EXPECT_DOUBLE_EQ(b.free_length(0.0, false, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(b.free_length(0.0, true, 0.5), 0.5);
  EXPECT_FALSE(b.rotation_clear(0.5));
  // Touching: a cell's square 1 cm off the side stops the body at once.
  b.gather(Pose2{0.0, 0.06, 0.0}, m.g);
  EXPECT_EQ(b.free_length(0.0, false, 0.5), 0.0);
}

// Following an edge: the nearest cell round where it was, never the far side of a gap.
TEST(BodyGuardTest, NearestAroundFollowsOneEdge) {
  Grid m;
  m.lethal(0.525, 0.625);   // left, 0.81 m
  m.lethal(0.575, 0.675);   // the same obstacle, farther
  m.lethal(0.525, -0.825);  // right, 0.98 m
  BodyGuard b = square();
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  EXPECT_NEAR(b.nearest().p.y(), 0.625, 1e-6);
  EXPECT_NEAR(b.nearest_around(Vec2(0.6, 0.7), 0.2).p.y(), 0.625, 1e-6);
  EXPECT_NEAR(b.nearest_around(Vec2(0.5, -0.8), 0.2).p.y(), -0.825, 1e-6);
  EXPECT_FALSE(b.nearest_around(Vec2(0.0, 0.0), 0.2).found);
  EXPECT_NEAR(b.distance_to(Vec2(0.525, 0.525)), 0.1, 1e-6);
}

TEST(BodyGuardTest, MoreCellsThanItHoldsBlocksEverything) {
  Grid m;
  for (int cy = -40; cy < 40; ++cy)
    for (int cx = -40; cx < 40; ++cx)
      if (std::hypot(cx, cy) > 8.0) m.g.at(cx, cy) = cost::kLethal;  // all but a 0.4 m disc
  BodyGuard b(0.25, 0.25, 0.05, 2.0);                                // ~4800 cells within 2 m
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  EXPECT_TRUE(b.crowded());
  EXPECT_EQ(b.free_length(0.0, false, 0.5), 0.0);
  EXPECT_FALSE(b.rotation_clear(0.1));
}

TEST(BodyGuardTest, ANonFinitePoseBlocksEverything) {
  Grid m;
  BodyGuard b = square();
  b.gather(Pose2{NAN, 0.0, 0.0}, m.g);
  EXPECT_TRUE(b.crowded());
  EXPECT_EQ(b.free_length(0.0, false, 0.5), 0.0);
  EXPECT_FALSE(b.rotation_clear(0.1));
  b.gather(Pose2{0.0, 0.0, 0.0}, m.g);
  EXPECT_FALSE(b.crowded());
}

}  // namespace
}  // namespace carril::fw
