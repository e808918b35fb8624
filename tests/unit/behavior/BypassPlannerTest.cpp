// BypassPlanner: side choice, blocked paths, waypoints, refinement.
#include "firmware/behavior/BypassPlanner.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/mapping/CostValues.hpp"
#include "tests/unit/behavior/BehaviorBuilders.hpp"

namespace carril::fw {
namespace {

using test::add_box;
using test::add_box_in;
using test::add_wall;
using test::field_of;
using test::World;

constexpr double kLane = 0.5 + 0.30 + 0.25;  // box half-width + clearance + robot half-width

class BypassPlannerTest : public testing::Test {
 protected:
  BypassPlan plan_from(const World& w, const Pose2& robot = {}, const Vec2& tape = Vec2::Zero(),
                       double heading = 0.0) const {
    return planner.plan(field_of(w, robot, fp), robot, tape, heading);
  }
  AvoidConfig cfg;
  Footprint fp;
  BypassPlanner planner{cfg, fp, false};
};

// A 1 m box on the tape 1 m ahead of the robot's centre.
World box_ahead() {
  World w;
  add_box(w, 1.0, 2.0, -0.5, 0.5);
  return w;
}

TEST_F(BypassPlannerTest, FreeBothSidesLaneIsHalfWidthPlusClearancePlusRobot) {
  const BypassPlan p = plan_from(box_ahead());
  ASSERT_TRUE(p.ok);
  EXPECT_FALSE(p.blocked);
  ASSERT_TRUE(p.side == 1 || p.side == -1);
  EXPECT_NEAR(p.lateral, p.side * kLane, 0.01);
  EXPECT_NEAR(p.x_near, 1.0, 0.005);
  EXPECT_NEAR(p.x_far, 2.0, 0.02);  // far side unseen: assumed as deep as wide
  EXPECT_NEAR(p.y_min, -0.5, 0.01);
  EXPECT_NEAR(p.y_max, 0.5, 0.01);
  EXPECT_DOUBLE_EQ(p.heading, 0.0);
}

TEST_F(BypassPlannerTest, WaypointsAsideThenPastThenBackOnTheTape) {
  const BypassPlan p = plan_from(box_ahead());
  ASSERT_TRUE(p.ok);
  ASSERT_EQ(p.waypoints.size(), 3U);
  const double past = p.x_far + cfg.clearance_m + fp.half_length_m;
  // Beside the robot.
  EXPECT_NEAR(p.waypoints[0].x(), 0.0, 1e-9);
  EXPECT_NEAR(p.waypoints[0].y(), p.lateral, 1e-9);
  // Past the far side by clearance + half length, still in the lane.
  EXPECT_NEAR(p.waypoints[1].x(), past, 1e-9);
  EXPECT_NEAR(p.waypoints[1].x(), 2.0 + 0.3 + 0.25, 0.02);
  EXPECT_NEAR(p.waypoints[1].y(), p.lateral, 1e-9);
  // Back on the tape, beyond.
  EXPECT_GT(p.waypoints[2].x(), past);
  EXPECT_NEAR(p.waypoints[2].y(), 0.0, 1e-9);
}

TEST_F(BypassPlannerTest, WallCloseOnOneSideGoesTheOtherWay) {
  for (const double wall_side : {1.0, -1.0}) {
    World w = box_ahead();
    add_wall(w, {-1.0, wall_side * 1.3}, {5.0, wall_side * 1.3});  // 0.8 m beside the box
    const BypassPlan p = plan_from(w);
    ASSERT_TRUE(p.ok) << "wall " << wall_side;
    EXPECT_EQ(p.side, -int(wall_side));
    EXPECT_NEAR(p.lateral, -wall_side * kLane, 0.01);
  }
}

TEST_F(BypassPlannerTest, BothSidesPassableChoosesTheFreerOne) {
  for (const double s : {1.0, -1.0}) {
    World w = box_ahead();
    add_wall(w, {-1.0, s * 1.8}, {5.0, s * 1.8});    // 1.3 m free
    add_wall(w, {-1.0, -s * 2.0}, {5.0, -s * 2.0});  // 1.5 m free
    const BypassPlan p = plan_from(w);
    ASSERT_TRUE(p.ok);
    EXPECT_EQ(p.side, -int(s));
  }
}

TEST_F(BypassPlannerTest, BothSidesAmpleChoosesTheShorterDetour) {
  World w;
  add_box(w, 1.0, 2.0, -0.3, 0.7);  // sticks out more to the left
  const BypassPlan p = plan_from(w);
  ASSERT_TRUE(p.ok);
  EXPECT_EQ(p.side, -1);
  EXPECT_NEAR(p.lateral, -(0.3 + 0.3 + 0.25), 0.01);
}

TEST_F(BypassPlannerTest, BothSidesTooNarrowIsBlocked) {
  World w = box_ahead();
  add_wall(w, {-1.0, 1.3}, {5.0, 1.3});
  add_wall(w, {-1.0, -1.3}, {5.0, -1.3});
  const BypassPlan p = plan_from(w);
  EXPECT_TRUE(p.blocked);
  EXPECT_FALSE(p.ok);
}

// A side already found blocked (LineBehavior backs out of it) is not chosen again, even where it
// is the freer one; with the other side walled off as well the plan is blocked.
TEST_F(BypassPlannerTest, AnExcludedSideIsNotChosenAgain) {
  for (const int side : {1, -1}) {
    World w = box_ahead();
    const Pose2 robot{};
    const BypassPlan free_choice = planner.plan(field_of(w, robot, fp), robot, Vec2::Zero(), 0.0);
    ASSERT_TRUE(free_choice.ok);
    const BypassPlan p =
        planner.plan(field_of(w, robot, fp), robot, Vec2::Zero(), 0.0, nullptr, side);
    ASSERT_TRUE(p.ok) << side;
    EXPECT_EQ(p.side, -side);
    EXPECT_NEAR(p.lateral, -side * kLane, 0.01);
    add_wall(w, {-1.0, -side * 1.3}, {5.0, -side * 1.3});  // the other side too narrow
    const BypassPlan q =
        planner.plan(field_of(w, robot, fp), robot, Vec2::Zero(), 0.0, nullptr, side);
    EXPECT_TRUE(q.blocked) << side;
    EXPECT_FALSE(q.ok);
  }
}

TEST_F(BypassPlannerTest, WiderThanTheMaximumDetourIsBlocked) {
  World w;
  add_box(w, 1.0, 1.3, -3.0, 3.0);
  const BypassPlan p = plan_from(w);
  EXPECT_TRUE(p.blocked);
  EXPECT_FALSE(p.ok);
}

TEST_F(BypassPlannerTest, NothingAheadIsNeitherOkNorBlocked) {
  World beside, behind;
  add_box(beside, 1.0, 2.0, 0.5, 1.0);  // outside the corridor (half-width 0.35)
  add_box(behind, -2.0, -1.0, -0.5, 0.5);
  for (const World& w : {World{}, beside, behind}) {
    const BypassPlan p = plan_from(w);
    EXPECT_FALSE(p.ok);
    EXPECT_FALSE(p.blocked);
    EXPECT_EQ(p.waypoints.size(), 0U);
  }
}

TEST_F(BypassPlannerTest, PlansInTheTapeFrame) {
  const Vec2 o(1.0, 2.0);
  const double h = 0.7;
  const Pose2 f{o.x(), o.y(), h};
  const Pose2 robot{to_world(f, {0.0, 0.1}).x(), to_world(f, {0.0, 0.1}).y(), h + 0.05};
  World w;
  add_box_in(w, o, h, 1.0, 2.0, -0.5, 0.5);
  const BypassPlan p = plan_from(w, robot, o, h);
  ASSERT_TRUE(p.ok);
  EXPECT_NEAR(std::fabs(p.lateral), kLane, 0.01);
  ASSERT_EQ(p.waypoints.size(), 3U);
  const Vec2 w0 = to_robot(f, p.waypoints[0]), w1 = to_robot(f, p.waypoints[1]),
             w2 = to_robot(f, p.waypoints[2]);
  EXPECT_NEAR(w0.x(), 0.0, 1e-9);
  EXPECT_NEAR(w0.y(), p.lateral, 1e-9);
  EXPECT_NEAR(w1.x(), 2.55, 0.02);
  EXPECT_NEAR(w1.y(), p.lateral, 1e-9);
  EXPECT_GT(w2.x(), w1.x());
  EXPECT_NEAR(w2.y(), 0.0, 1e-9);
}

TEST_F(BypassPlannerTest, RefineExtendsThePlanWhenTheFarSideShows) {
  World w;
  add_box(w, 1.0, 3.0, -0.5, 0.5);  // 2 m deep
  BypassPlan p = plan_from(w);
  ASSERT_TRUE(p.ok);
  ASSERT_NEAR(p.x_far, 2.0, 0.02);
  const BypassPlan before = p;
  // The same view again: nothing new.
  planner.refine(field_of(w, Pose2{}, fp), p);
  EXPECT_DOUBLE_EQ(p.x_far, before.x_far);
  EXPECT_EQ(p.waypoints[1], before.waypoints[1]);
  // From the passing lane the whole side is in view.
  const Pose2 beside{1.5, p.lateral, 0.0};
  planner.refine(field_of(w, beside, fp), p);
  EXPECT_NEAR(p.x_far, 3.0, 0.02);
  ASSERT_EQ(p.waypoints.size(), 3U);
  EXPECT_NEAR(p.waypoints[0].x(), before.waypoints[0].x(), 1e-9);  // still beside the robot
  EXPECT_NEAR(p.waypoints[0].y(), p.lateral, 1e-9);
  EXPECT_GE(std::fabs(p.lateral), std::fabs(before.lateral));  // the lane never moves closer
  EXPECT_NEAR(p.waypoints[1].x(), 3.0 + 0.3 + 0.25, 0.02);
  EXPECT_NEAR(p.waypoints[1].y(), p.lateral, 1e-9);
  EXPECT_GT(p.waypoints[2].x(), p.waypoints[1].x());
  EXPECT_NEAR(p.waypoints[2].y(), 0.0, 1e-9);
  EXPECT_NEAR(std::fabs(p.lateral), kLane, 0.01);  // not wider: same lane
}

// Wider further back than its front face (hidden behind it from the first view): once seen from
// the passing lane, the lane moves out to keep the clearance.
TEST_F(BypassPlannerTest, RefineMovesTheLaneOutWhenTheObstacleWidens) {
  World w;
  add_box(w, 1.0, 2.0, -0.5, 0.5);
  add_box(w, 2.0, 2.6, -0.5, 0.6);
  BypassPlan p = plan_from(w);
  ASSERT_TRUE(p.ok);
  ASSERT_EQ(p.side, 1);  // both sides free and the front looks symmetric: left
  ASSERT_NEAR(p.lateral, kLane, 0.01);
  planner.refine(field_of(w, Pose2{1.5, p.lateral, 0.0}, fp), p);
  EXPECT_NEAR(p.y_max, 0.6, 0.01);
  EXPECT_NEAR(p.lateral, 0.6 + 0.3 + 0.25, 0.01);
  EXPECT_NEAR(p.x_far, 2.6, 0.02);
  ASSERT_EQ(p.waypoints.size(), 3U);
  EXPECT_NEAR(p.waypoints[0].y(), p.lateral, 1e-9);
  EXPECT_NEAR(p.waypoints[1].y(), p.lateral, 1e-9);
  EXPECT_NEAR(p.waypoints[1].x(), 2.6 + 0.3 + 0.25, 0.02);
  // A later view that misses the wide part does not bring the lane back in.
  const double lane = p.lateral;
  planner.refine(field_of(box_ahead(), Pose2{}, fp), p);
  EXPECT_DOUBLE_EQ(p.lateral, lane);
}

TEST_F(BypassPlannerTest, RefineLeavesAFailedPlanAlone) {
  BypassPlan p;  // ok == false
  planner.refine(field_of(box_ahead(), Pose2{}, fp), p);
  EXPECT_FALSE(p.ok);
  EXPECT_EQ(p.waypoints.size(), 0U);
}

// A free 10 m x 10 m costmap round the origin at 5 cm, with lethal cells at `points`.
RollingGrid<std::uint8_t> costmap_with(std::initializer_list<Vec2> points) {
  RollingGrid<std::uint8_t> g;
  g.init(200, 200, 0.05, cost::kFree);
  g.recenter(0.0, 0.0);
  for (const Vec2& q : points) {
    int cx = 0, cy = 0;
    if (g.world_to_cell(q.x(), q.y(), cx, cy)) g.at(cx, cy) = cost::kLethal;
  }
  return g;
}

// The lane check keeps the whole body off lethal cells, not only its centre: a post 3 cm beyond
// the front of the body where the lane ends (the centre 0.28 m from it, further than the robot's
// inscribed radius) closes the lane; 30 cm further on (clear of the turn onto the way back) it
// does not.
TEST_F(BypassPlannerTest, TheLaneCheckKeepsTheWholeBodyOffLethalCells) {
  const BypassPlan p = plan_from(box_ahead());
  ASSERT_TRUE(p.ok);
  const Vec2 past = p.waypoints[1];
  const Vec2 clip(past.x() + fp.half_length_m + 0.03, past.y());
  EXPECT_FALSE(planner.lane_clear(p, Pose2{}, 0, costmap_with({clip})));
  EXPECT_TRUE(planner.lane_clear(p, Pose2{}, 0, costmap_with({clip + Vec2(0.3, 0.0)})));
  EXPECT_TRUE(planner.lane_clear(p, Pose2{}, 0, costmap_with({})));
  // Planned with that costmap, the post sends the robot round the other side.
  const RollingGrid<std::uint8_t> cm = costmap_with({clip});
  const BypassPlan q =
      planner.plan(field_of(box_ahead(), Pose2{}, fp), Pose2{}, Vec2::Zero(), 0.0, &cm);
  ASSERT_TRUE(q.ok);
  EXPECT_EQ(q.side, -p.side);
  // ...and with both sides' lanes closed the plan is blocked.
  const Vec2 other(clip.x(), -clip.y());
  const RollingGrid<std::uint8_t> both = costmap_with({clip, other});
  const BypassPlan r =
      planner.plan(field_of(box_ahead(), Pose2{}, fp), Pose2{}, Vec2::Zero(), 0.0, &both);
  EXPECT_TRUE(r.blocked);
  EXPECT_FALSE(r.ok);
}

// The costmap may hold more of the obstacle than the scan's outline (a lidar on one corner sees one
// flank; thesis campaign variant 262): the lane moves out until the body clears it, rather than
// giving up that side.
TEST_F(BypassPlannerTest, ALaneTheCostmapClosesMovesOut) {
  const BypassPlan p = plan_from(box_ahead());
  ASSERT_TRUE(p.ok);
  ASSERT_EQ(p.side, 1);  // both sides free: the shorter detour, left on a tie
  std::initializer_list<Vec2> flank = {{1.2, 0.72}, {1.5, 0.72}, {1.8, 0.72}};
  const RollingGrid<std::uint8_t> cm = costmap_with(flank);
  EXPECT_FALSE(planner.lane_clear(p, Pose2{}, 0, cm));
  const BypassPlan q =
      planner.plan(field_of(box_ahead(), Pose2{}, fp), Pose2{}, Vec2::Zero(), 0.0, &cm);
  ASSERT_TRUE(q.ok);
  EXPECT_EQ(q.side, 1);
  EXPECT_NEAR(q.lateral, kLane + BypassPlanner::kLaneStepM, 0.01);
  EXPECT_TRUE(planner.lane_clear(q, Pose2{}, 0, cm));
}

// A differential robot turns on the spot where the leg aside ends, sweeping the circle round its
// corners; a holonomic one slides on, facing along the tape. A post inside that circle but clear
// of the sliding body closes only the differential robot's lane.
TEST_F(BypassPlannerTest, ADifferentialRobotsTurnOnTheSpotIsChecked) {
  const Footprint longer{0.5, 0.2};
  const BypassPlanner diff(cfg, longer, false), holo(cfg, longer, true);
  const BypassPlan p =
      diff.plan(field_of(box_ahead(), Pose2{}, longer), Pose2{}, Vec2::Zero(), 0.0);
  ASSERT_TRUE(p.ok);
  const Vec2 aside = p.waypoints[0];  // (0, lateral)
  const double out = p.side;          // away from the tape
  // 0.53 m from the turn's centre (circumscribed radius 0.54), 0.15 m beyond the side of the body.
  const RollingGrid<std::uint8_t> cm = costmap_with({aside + Vec2(-0.4, out * 0.35)});
  EXPECT_FALSE(diff.lane_clear(p, Pose2{}, 0, cm));
  EXPECT_TRUE(holo.lane_clear(p, Pose2{}, 0, cm));
}

// What stopped the robot may stand beside the tape once it has turned onto it; the next thing
// down the tape (a wall 8 m on) is not planned round until it is within lookahead_m of the bumper.
TEST_F(BypassPlannerTest, AnObstacleBeyondTheLookaheadIsNotPlannedRound) {
  World w;
  add_box(w, 3.0, 4.0, -0.5, 0.5);  // 2.75 m from the bumper
  EXPECT_FALSE(plan_from(w).ok);
  EXPECT_FALSE(plan_from(w).blocked);
  AvoidConfig far = cfg;
  far.lookahead_m = 3.0;
  const BypassPlanner further(far, fp, false);
  EXPECT_TRUE(further.plan(field_of(w, Pose2{}, fp), Pose2{}, Vec2::Zero(), 0.0).ok);
}

// Two boxes 0.6 m apart on the tape: no room to rejoin between them (a body length and the
// clearance each side), so one bypass passes both, its far end beyond the second (issue 46).
TEST_F(BypassPlannerTest, AnObstacleWhereTheRobotWouldRejoinIsPassedInTheSameBypass) {
  World w;
  add_box(w, 1.0, 1.5, -0.25, 0.1);
  add_box(w, 2.1, 2.6, -0.1, 0.5);  // its left part shows past the first's
  const BypassPlan p = plan_from(w);
  ASSERT_TRUE(p.ok);
  // Its far side unseen, it is taken to be as deep as the part in view is wide (0.29 m).
  EXPECT_GT(p.x_far, 2.3);
  EXPECT_GE(p.y_max, 0.5 - 0.01);
  const double past = p.x_far + cfg.clearance_m + fp.half_length_m;
  ASSERT_EQ(p.waypoints.size(), 3U);
  EXPECT_NEAR(p.waypoints[1].x(), past, 1e-9);
  // Hidden behind the first (not in the scan), the costmap's marks of the second do the same.
  World first;
  add_box(first, 1.0, 1.5, -0.25, 0.25);
  const RollingGrid<std::uint8_t> g =
      costmap_with({Vec2(2.12, 0.02), Vec2(2.27, 0.02), Vec2(2.42, 0.02), Vec2(2.57, 0.02)});
  const BypassPlan q = planner.plan(field_of(first, Pose2{}, fp), Pose2{}, Vec2::Zero(), 0.0, &g);
  ASSERT_TRUE(q.ok);
  EXPECT_GE(q.x_far, 2.55);
  // Beyond rejoining reach (2 m on), the second is not this bypass's business.
  World apart;
  add_box(apart, 1.0, 1.5, -0.25, 0.25);
  add_box(apart, 3.6, 4.1, -0.25, 0.25);
  const BypassPlan r = plan_from(apart);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.x_far, 2.1);
}

}  // namespace
}  // namespace carril::fw
