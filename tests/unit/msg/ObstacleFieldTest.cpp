// Lidar input that real drivers produce and that must never crash or fool the firmware: NaN
// (invalid), +inf (no return within range), -inf (too close to measure), zero and out-of-limit
// ranges. Runs with floating-point traps on,
// so comparing a NaN anywhere would stop the test.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "firmware/msg/ObstacleField.hpp"

namespace carril::fw {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A 9-beam scan from -40 to +40 deg, sensor at the robot centre facing forward.
std::unique_ptr<hal::LaserScan> scan_of(std::initializer_list<float> ranges) {
  auto s = std::make_unique<hal::LaserScan>();
  s->seq = 1;
  s->angle_min_rad = float(-40.0 * kPi / 180.0);
  s->angle_increment_rad = float(10.0 * kPi / 180.0);
  s->range_min_m = 0.05F;
  s->range_max_m = 10.0F;
  s->count = static_cast<std::uint16_t>(ranges.size());
  std::size_t i = 0;
  for (float r : ranges) s->ranges_m[i++] = r;
  return s;
}

TEST(ObstacleFieldTest, InvalidRangesAreSkippedAndCounted) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0);
  // NaN, +inf, 0, negative, under range_min, over range_max, -inf, and two valid returns.
  auto s = scan_of({kNaN, kInf, 0.0F, -1.0F, 0.01F, 12.0F, -kInf, 1.0F, 2.0F});
  f.update(*s, Pose2{});
  EXPECT_TRUE(f.valid());
  EXPECT_EQ(f.points().size(), 3U);
  EXPECT_EQ(f.invalid_beams(), 6U);
  // -inf at +20 deg is an obstacle at range_min; the two valid beams are at +30 and +40 deg.
  EXPECT_NEAR(f.points()[0].norm(), 0.05, 1e-6);
  EXPECT_NEAR(f.points()[1].x(), std::cos(30 * kPi / 180), 1e-6);
  EXPECT_NEAR(f.points()[2].y(), 2.0 * std::sin(40 * kPi / 180), 1e-6);
}

TEST(ObstacleFieldTest, TooCloseToMeasureIsAnObstacleAgainstTheBody) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0);
  auto s = scan_of({kInf, kInf, kInf, kInf, -kInf, kInf, kInf, kInf, kInf});
  f.update(*s, Pose2{});
  ASSERT_EQ(f.points().size(), 1U);
  EXPECT_LT(f.clearance_m(Pose2{}), 1e-9);  // inside the footprint: stop
}

TEST(ObstacleFieldTest, AllNaNScanMeansNothingAhead) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0);
  auto s = scan_of({kNaN, kNaN, kNaN, kNaN, kNaN});
  f.update(*s, Pose2{});
  EXPECT_TRUE(f.points().empty());
  EXPECT_EQ(f.ahead_m(Pose2{}, 0.1, 5.0), 5.0);
  EXPECT_GT(f.clearance_m(Pose2{}), 1e6);
}

TEST(ObstacleFieldTest, DistancesAreFromTheFootprintNotTheSensor) {
  // Sensor on the front-right corner, turned 45 deg right (campero's mount): a wall 1 m ahead of
  // the bumper is 1 m ahead whatever the beam it is seen on.
  const double mx = 0.45, my = -0.35, myaw = -kPi / 4;
  ObstacleField f({0.49, 0.39}, mx, my, myaw);
  auto s = std::make_unique<hal::LaserScan>();
  s->seq = 1;
  s->angle_min_rad = float(-3 * kPi / 4);
  s->angle_increment_rad = float(kPi / 180.0);
  s->range_min_m = 0.05F;
  s->range_max_m = 20.0F;
  s->count = 271;
  const double wall_x = 0.49 + 1.0;
  for (int i = 0; i < 271; ++i) {
    const double a = double(s->angle_min_rad) + i * double(s->angle_increment_rad) + myaw;
    const double c = std::cos(a);
    s->ranges_m[std::size_t(i)] = c > 0.05 ? float((wall_x - mx) / c) : kInf;
  }
  f.update(*s, Pose2{});
  EXPECT_NEAR(f.ahead_m(Pose2{}, 0.1, 5.0), 1.0, 1e-3);
  EXPECT_NEAR(f.clearance_m(Pose2{}), 1.0, 1e-3);
}

// The beams' directions are kept between scans of the same geometry; a scan with another start
// angle, increment or count gets its own (as a different scanner, or a reconfigured one, would).
TEST(ObstacleFieldTest, AScanOfAnotherGeometryIsNotSeenThroughTheLastOnesDirections) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0);
  auto s = scan_of({2.0F, 2.0F, 2.0F, 2.0F, 2.0F, 2.0F, 2.0F, 2.0F, 2.0F});
  const auto expect_points = [&](const char* what) {
    ASSERT_EQ(int(f.points().size()), int(s->count)) << what;
    for (int i = 0; i < s->count; ++i) {
      const double a = double(s->angle_min_rad) + i * double(s->angle_increment_rad);
      EXPECT_NEAR(f.points()[std::size_t(i)].x(), 2.0 * std::cos(a), 1e-12) << what << " " << i;
      EXPECT_NEAR(f.points()[std::size_t(i)].y(), 2.0 * std::sin(a), 1e-12) << what << " " << i;
    }
  };
  f.update(*s, Pose2{});
  expect_points("first");
  s->angle_min_rad = float(-20.0 * kPi / 180.0);
  f.update(*s, Pose2{});
  expect_points("start angle changed");
  s->angle_increment_rad = float(3.0 * kPi / 180.0);
  f.update(*s, Pose2{});
  expect_points("increment changed");
  s->count = 5;
  f.update(*s, Pose2{});
  expect_points("fewer beams");
  s->count = 9;
  s->ranges_m[8] = 2.0F;
  f.update(*s, Pose2{});
  expect_points("more beams again");
}

// The scanner sees 80 deg ahead; a return at +40 deg, 0.45 m out, is then turned away from.
TEST(ObstacleFieldTest, WhatLeftTheFieldOfViewIsRememberedForTheTurn) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0, 1.5);
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, 0.45F}), Pose2{});
  const Vec2 seen = f.points()[0];
  // Turned 90 deg right: the return is behind the left side, where no beam looks.
  const Pose2 turned{0.0, 0.0, -kPi / 2};
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), turned);
  EXPECT_EQ(f.points().size(), 0U);
  ASSERT_EQ(f.remembered().size(), 1U);
  EXPECT_NEAR((f.remembered()[0] - seen).norm(), 0.0, 1e-12);
  EXPECT_EQ(f.clearance_m(turned), 1e9);  // the scan alone: nothing near
  // From the 0.5 x 0.5 m body: 0.345 - 0.25 one way, 0.289 - 0.25 the other.
  const double dx = 0.45 * std::sin(40 * kPi / 180) - 0.25;
  const double dy = 0.45 * std::cos(40 * kPi / 180) - 0.25;
  EXPECT_NEAR(f.clearance_all_round_m(turned), std::hypot(dx, dy), 1e-6);
  // Turned back: a beam that ends nearer hides it (kept), a NaN says nothing (kept), a beam that
  // reaches it or looks past it (a return beyond, or +inf: nothing within range) clears it.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, 0.35F}), Pose2{});
  EXPECT_EQ(f.remembered().size(), 1U);
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kNaN}), Pose2{});
  EXPECT_EQ(f.remembered().size(), 2U);  // and the 0.35 m return, which no beam looked past
  // A return 2 m out along that beam: it looked past both.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, 2.0F}), Pose2{});
  EXPECT_EQ(f.remembered().size(), 0U);
  // Nothing within range along it: it looked past the 2 m return too.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), Pose2{});
  EXPECT_EQ(f.remembered().size(), 0U);
  EXPECT_EQ(f.clearance_all_round_m(Pose2{}), 1e9);
}

// Behind the rear bumper: what the scan shows there and what is remembered of it (a scanner that
// sees only ahead shows nothing behind).
TEST(ObstacleFieldTest, BehindCountsTheRememberedReturnsTheScanNoLongerShows) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0, 1.5);
  // Straight ahead, 0.8 m out: 0.55 m from the front bumper; nothing behind yet.
  f.update(*scan_of({kInf, kInf, kInf, kInf, 0.8F, kInf, kInf, kInf, kInf}), Pose2{});
  EXPECT_NEAR(f.ahead_m(Pose2{}, 0.1, 5.0), 0.55, 1e-6);
  EXPECT_EQ(f.behind_m(Pose2{}, 0.1, 5.0), 5.0);
  // Facing the other way, 0.2 m farther off: the return is behind, seen by no beam now.
  const Pose2 away{-0.2, 0.0, kPi};
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), away);
  ASSERT_EQ(f.remembered().size(), 1U);
  EXPECT_EQ(f.ahead_m(away, 0.1, 5.0), 5.0);
  EXPECT_NEAR(f.behind_m(away, 0.1, 5.0), 0.75, 1e-6);
  // Off to the side of the corridor (0.25 + 0.1 m half wide) it does not count.
  EXPECT_EQ(f.behind_m(Pose2{-0.2, 0.4, kPi}, 0.1, 5.0), 5.0);
  // And the scan's own points count: facing it again, backed off, it is ahead, not behind.
  f.update(*scan_of({kInf, kInf, kInf, kInf, 1.0F, kInf, kInf, kInf, kInf}), Pose2{-0.2, 0, 0});
  EXPECT_EQ(f.behind_m(Pose2{-0.2, 0, 0}, 0.1, 5.0), 5.0);
  EXPECT_NEAR(f.behind_m(Pose2{-0.2, 0, kPi}, 0.1, 5.0), 0.75, 1e-6);
}

// Not asked to remember (no lost turn configured): the scan alone, at no cost per scan.
TEST(ObstacleFieldTest, NotAskedToRememberItKeepsNothing) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0);
  // 0.34 m out at +40 deg: outside the body, inside the circle it sweeps.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, 0.34F}), Pose2{});
  const Pose2 turned{0.0, 0.0, -kPi / 2};
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), turned);
  EXPECT_EQ(f.remembered().size(), 0U);
  EXPECT_EQ(f.clearance_all_round_m(turned), 1e9);
}

TEST(ObstacleFieldTest, ARememberedReturnIsForgottenWhereTheBodyNowStandsOrFarAway) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0, 1.5);
  f.update(*scan_of({kInf, kInf, kInf, kInf, 0.8F, kInf, kInf, kInf, kInf}), Pose2{});
  // Backed away facing the other way: the return, 0.8 m ahead of the start, is behind.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), Pose2{0.0, 0, kPi});
  EXPECT_EQ(f.remembered().size(), 1U);
  // The body now over it (driven there backwards): whatever it was is gone.
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), Pose2{0.7, 0, kPi});
  EXPECT_EQ(f.remembered().size(), 0U);
  // Far away: beyond the reach round the body it is not kept either.
  f.update(*scan_of({kInf, kInf, kInf, kInf, 0.8F, kInf, kInf, kInf, kInf}), Pose2{});
  f.update(*scan_of({kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf}), Pose2{-3.0, 0, kPi});
  EXPECT_EQ(f.remembered().size(), 0U);
}

// More returns than it can hold: it cannot vouch for a turn, so none is cleared.
TEST(ObstacleFieldTest, AMemoryThatOverflowsClearsNoTurn) {
  ObstacleField f({0.25, 0.25}, 0.0, 0.0, 0.0, 1.5);
  auto s = std::make_unique<hal::LaserScan>();
  s->seq = 1;
  s->angle_min_rad = float(-kPi / 2);
  s->count = 1200;
  s->angle_increment_rad = float(kPi / 1199);
  s->range_min_m = 0.05F;
  s->range_max_m = 10.0F;
  // Alternating 0.6 m and 1.4 m: no two neighbours within the thinning's spacing.
  for (std::size_t i = 0; i < s->count; ++i) s->ranges_m[i] = i % 2 == 0 ? 0.6F : 1.4F;
  f.update(*s, Pose2{});
  for (std::size_t i = 0; i < s->count; ++i) s->ranges_m[i] = kInf;
  const Pose2 back{0.0, 0.0, kPi};
  f.update(*s, back);
  EXPECT_TRUE(f.memory_overflowed());
  EXPECT_EQ(f.clearance_all_round_m(back), 0.0);
  EXPECT_EQ(f.clearance_m(back), 1e9);
}

}  // namespace
}  // namespace carril::fw
