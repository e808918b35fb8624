// The waypoint mission with a square body that turns: its corners must clear what it turns next
// to. The simulator's course (scenarios/waypoints_vff.yaml: posts and turned boxes on every
// leg, a pioneer3at 0.508 x 0.497 m, the firmware's acceleration limits) driven twice round
// without the body's rectangle ever touching a lethal cell; and a robot parked with a box corner
// inside its swept circle moves back before it turns.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "firmware/mission/WaypointMission.hpp"
#include "tests/unit/mission/WaypointHarness.hpp"

namespace carril::fw {
namespace {

using test_waypoints::Bench;
using test_waypoints::counter;
using test_waypoints::CourseCostmap;

constexpr double kDeg = kPi / 180.0;

// The scenario's room: 8.5 x 7 m inside walls 0.1 m thick, three posts and three turned boxes,
// each on the line between two targets. Odometry frame = world frame (start at the origin).
struct SimCourse {
  SimCourse() : map(-2.0, -2.0, 200, 160), bench(&map) {
    map.box(2.75, -1.5, 0.0, 8.6, 0.1);  // walls
    map.box(2.75, 5.5, 0.0, 8.6, 0.1);
    map.box(-1.5, 2.0, 0.0, 0.1, 7.1);
    map.box(7.0, 2.0, 0.0, 0.1, 7.1);
    map.post(2.0, 0.2, true, 0.25);
    map.box(4.8, 2.0, 30.0 * kDeg, 0.6, 0.6);
    map.post(3.5, 3.8, true, 0.3);
    map.box(0.5, 3.0, 0.0, 0.5, 0.8);
    map.post(-0.3, 1.0, true, 0.2);
    map.box(3.0, 1.5, 45.0 * kDeg, 0.4, 0.4);
    WaypointConfig& c = bench.cfg;
    for (const Vec2& t :
         {Vec2(4.0, 0.5), Vec2(5.5, 3.5), Vec2(1.5, 4.0), Vec2(-0.5, 2.0), Vec2(0.0, 0.0)}) {
      c.targets.push_back(t);
    }
    c.laps = 2;
    c.reach_radius_m = 0.3;
    c.speed_mps = 0.4;
    c.vff.cruise_speed_mps = 0.4;
    bench.footprint = Footprint{0.254, 0.2485};
    bench.max_accel_mps2 = 1.0;  // the pioneer3at's limits
    bench.max_yaw_accel_radps2 = 3.0;
  }
  CourseCostmap map;
  Bench bench;
};

TEST(WaypointCourseTest, TheSimulatorsCourseTwiceRoundWithoutTheBodyTouching) {
  SimCourse s;
  Bench& b = s.bench;
  ASSERT_TRUE(b.cfg.validate()) << b.cfg.validate().message();
  b.start();
  b.run(240.0);
  ASSERT_EQ(b.mission->current(), WaypointMission::State::Done) << b.mission->state().phase;
  EXPECT_EQ(b.order, (std::vector<std::size_t>{0, 1, 2, 3, 4, 0, 1, 2, 3, 4}));
  EXPECT_EQ(b.mission->targets_skipped(), 0u);
  // The body's rectangle (corners included) keeps clear of every cell, turning or not.
  EXPECT_GT(b.min_body_clearance, 0.05);
  ASSERT_EQ(b.mission->lap_times().size(), 2u);
  EXPECT_LT(b.mission->lap_times()[0] + b.mission->lap_times()[1], 200.0);
  std::printf("laps %.2f s, %.2f s; body clearance %.3f m; stops %u, bypasses %u, escapes %u\n",
              b.mission->lap_times()[0], b.mission->lap_times()[1], b.min_body_clearance,
              b.mission->emergency_stops(), b.mission->bypasses(), b.mission->escapes());
}

// A box's corner 3 cm off the body's left side, near its front corner: inside the circle the
// corners sweep, outside the strip ahead of the front edge. The target lies to the left: turning
// at once would swing the front corner into the box. The robot first moves back to where the
// turn is clear, then turns and drives on.
TEST(WaypointCourseTest, MovesBackBeforeTurningWhenACornerWouldTouch) {
  Bench b;
  b.costmap.box(0.3, 0.43, 0.0, 0.3, 0.3);  // corner (0.15, 0.28)
  b.cfg.targets.push_back(Vec2(-0.5, 2.5));
  b.max_accel_mps2 = 1.0;
  b.max_yaw_accel_radps2 = 3.0;
  b.start();
  ASSERT_GT(b.costmap.body_clearance(b.pose, b.footprint), 0.0);
  b.run(60.0);
  EXPECT_EQ(b.mission->current(), WaypointMission::State::Done) << b.mission->state().phase;
  EXPECT_GT(b.min_body_clearance, 0.0);
  EXPECT_GE(b.mission->escapes(), 1u);
  EXPECT_EQ(counter(*b.mission, "escapes"), b.mission->escapes());
}

// Between the course's box (0.5, 3.0) and its post (-0.3, 1.0), 1.5 m apart, toward the target
// (-0.5, 2.0) beyond: VFF pushed by the inflated band round both would fill its push's cap with a
// push square against the pull, and the heading would swing to and fro (5 to 6 rad of turning);
// pushed by the lethal cells only, the robot drives through nearly straight.
TEST(WaypointCourseTest, DrivesStraightThroughAGapBetweenTwoObstacles) {
  for (double y0 : {1.4, 1.6, 1.8}) {
    SCOPED_TRACE(y0);
    SimCourse s;
    Bench& b = s.bench;
    b.cfg.targets.clear();
    b.cfg.targets.push_back(Vec2(-0.5, 2.0));
    b.cfg.laps = 1;
    b.pose = Pose2{1.2, y0, 3.0};
    b.start();
    b.run(30.0);
    EXPECT_EQ(b.mission->current(), WaypointMission::State::Done);
    EXPECT_LT(b.turned_rad, 1.0);  // at least 0.1 rad to face the target
    EXPECT_EQ(b.mission->bypasses(), 0u);
  }
}

// A U-shaped pocket opening toward the robot, the target behind its bottom: VFF drives into the
// pocket and the robot goes round from its bottom. Its corridor to the target clears in the
// pocket's mouth, farther from the target than where the bypass began; left there, VFF would
// drive it back in, bypass and leave again until the timeout. It leaves only closer to the
// target than it ever was before the bypass (as in Bug2), here round the pocket's outside.
TEST(WaypointCourseTest, ABypassEndsOnlyCloserToTheTargetThanItBegan) {
  Bench b;
  b.costmap.box(2.0, 0.0, 0.0, 0.1, 2.1);  // the bottom
  b.costmap.box(1.4, 1.0, 0.0, 1.3, 0.1);  // the arms
  b.costmap.box(1.4, -1.0, 0.0, 1.3, 0.1);
  b.cfg.targets.push_back(Vec2(3.5, 0.0));
  b.start();
  b.run(120.0);
  ASSERT_EQ(b.mission->current(), WaypointMission::State::Done) << b.mission->state().phase;
  EXPECT_GE(b.mission->bypasses(), 1u);
  for (std::size_t i = 1; i < b.phases.size(); ++i) {
    if (b.phases[i] != "drive" || b.phases[i - 1] != "bypass") continue;
    EXPECT_LT(b.phase_dist[i], b.phase_dist[i - 1]) << "bypass left at change " << i;
  }
  EXPECT_GT(b.min_body_clearance, 0.05);
}

}  // namespace
}  // namespace carril::fw
