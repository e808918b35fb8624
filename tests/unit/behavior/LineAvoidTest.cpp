// LineBehavior AVOID: stop, align, plan, bypass (with refinement and the emergency stop),
// rejoin; the scans are ray-cast against boxes and walls from the simulated pose every tick.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "firmware/behavior/LineBehavior.hpp"
#include "tests/unit/behavior/BehaviorBuilders.hpp"

namespace carril::fw {
namespace {

using test::add_box;
using test::add_wall;
using test::expect_still;
using test::Phases;
using test::Sim;

double ahead(const Sim& s) {
  return s.field.ahead_m(s.last_in.odom, s.stop.corridor_margin_m, 5.0);
}

// Phases from the first "stop" on.
Phases avoid_phases(const Sim& s) {
  auto it = std::find(s.phases.begin(), s.phases.end(), "stop");
  return Phases(it, s.phases.end());
}

TEST(LineBehaviorAvoidTest, ObstacleAheadStopsTheRobot) {
  Sim s(true);
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::Avoid, 1000));
  EXPECT_STREQ(s.mb.phase(), "stop");
  EXPECT_LT(ahead(s), s.stop.stop_m);
  EXPECT_GT(ahead(s), s.stop.stop_m - 0.01);  // the first tick it was that close
  expect_still(s.out.twist);
  EXPECT_EQ(s.mb.obstacles_avoided(), 0U);
  EXPECT_FALSE(s.out.clear_map);
}

TEST(LineBehaviorAvoidTest, ObstacleBesideTheCorridorIsIgnored) {
  Sim s(false);
  // Corridor: robot half-width 0.25 + margin 0.10; this box starts 0.12 m outside it.
  add_box(s.world, 1.0, 1.5, 0.47, 0.9);
  add_box(s.world, 2.0, 2.5, -0.9, -0.47);
  s.start_on_tape();
  for (int i = 0; i < 700; ++i) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Follow) << "x=" << s.pose.x;
  }
  EXPECT_GT(s.pose.x, 3.0);
}

TEST(LineBehaviorAvoidTest, StopWaitsUntilTheMeasuredTwistIsZero) {
  Sim s(false);
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::Avoid, 1000));
  for (const Twist m :
       {Twist{0.1, 0, 0}, Twist{0.0, 0.03, 0.0}, Twist{0.0, 0.0, 0.08}, Twist{-0.05, 0, 0}}) {
    s.script = [m](BehaviorInput& in) { in.measured = m; };
    for (int i = 0; i < 20; ++i) {
      s.step();
      ASSERT_STREQ(s.mb.phase(), "stop");
      expect_still(s.out.twist);
    }
  }
  s.script = [](BehaviorInput& in) { in.measured = {0.015, -0.015, 0.04}; };  // still enough
  s.step();
  EXPECT_EQ(s.mb.state(), LineState::Avoid);
  EXPECT_STREQ(s.mb.phase(), "align");
}

// The tape frame comes from the far end of the remembered tape when there is one (where it runs
// into the obstacle), else from the track under the robot.
class LineBehaviorAvoidAlign : public testing::TestWithParam<bool> {};

TEST_P(LineBehaviorAvoidAlign, TurnsToTheTapeHeadingBeforePlanning) {
  Sim s(false);
  s.far_from_map = GetParam();
  s.pose = Pose2{1.0, 0.0, 0.2};  // on the tape, turned 0.2 rad to its left
  add_box(s.world, 1.6, 2.6, -0.5, 0.5);
  s.start_on_tape();
  ASSERT_EQ(s.mb.state(), LineState::Follow);
  ASSERT_TRUE(s.run_until_phase("align", 5));
  const Pose2 p0 = s.pose;
  ASSERT_TRUE(s.run_until(
      [&] {
        if (std::string(s.mb.phase()) == "align") {
          EXPECT_LT(s.out.twist.wz, 0.0);
          EXPECT_EQ(s.out.twist.vx, 0.0);
          EXPECT_EQ(s.out.twist.vy, 0.0);
        }
        return std::string(s.mb.phase()) != "align";
      },
      500));
  EXPECT_STREQ(s.mb.phase(), "bypass");
  EXPECT_LT(std::fabs(s.pose.yaw), s.cfg.align_tolerance_rad);
  EXPECT_EQ(s.pose.x, p0.x);
  EXPECT_EQ(s.pose.y, p0.y);
  EXPECT_DOUBLE_EQ(s.mb.bypass().heading, 0.0);  // the tape's, not the robot's
  EXPECT_NEAR(s.mb.bypass().origin.y(), 0.0, 1e-9);
  if (!s.far_from_map) EXPECT_NEAR(s.mb.bypass().origin.x(), 1.0, 1e-9);  // under the robot
  EXPECT_NEAR(std::fabs(s.mb.bypass().lateral), 0.5 + 0.3 + 0.25, 0.01);
}

INSTANTIATE_TEST_SUITE_P(TapeFrom, LineBehaviorAvoidAlign, testing::Values(true, false),
                         [](const auto& i) { return i.param ? "FarSegment" : "Track"; });

// The tape turns 0.6 rad left at x = 1.6 and the box stands on the new stretch: the bypass runs
// along that stretch, not along the robot's heading.
TEST(LineBehaviorAvoidTest, PassesAlongTheTapeWhereItRunsIntoTheObstacle) {
  Sim s(true);
  const double h = 0.6;
  const Vec2 bend(1.6, 0.0), u(std::cos(h), std::sin(h));
  test::add_box_in(s.world, bend, h, 0.6, 1.4, -0.4, 0.4);
  s.script = [&](BehaviorInput& in) {
    in.tape_far_valid = in.track.valid;
    in.tape_far_point = bend + 0.3 * u;
    in.tape_far_heading = h;
  };
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_phase("align", 1000));
  ASSERT_TRUE(s.run_until_phase("bypass", 500));
  EXPECT_NEAR(s.pose.yaw, h, s.cfg.align_tolerance_rad);
  const BypassPlan& p = s.mb.bypass();
  EXPECT_DOUBLE_EQ(p.heading, h);
  EXPECT_NEAR(std::fabs(p.lateral), 0.4 + 0.3 + 0.25, 0.015);
  const Pose2 frame{bend.x(), bend.y(), h};
  ASSERT_EQ(p.waypoints.size(), 3U);
  EXPECT_NEAR(to_robot(frame, p.waypoints[1]).x(), 1.4 + 0.3 + 0.25, 0.03);
  EXPECT_NEAR(to_robot(frame, p.waypoints[2]).y(), 0.0, 1e-9);
  double min_clearance = 1e9;
  ASSERT_TRUE(s.run_until(
      [&] {
        min_clearance = std::fmin(min_clearance, s.field.clearance_m(s.last_in.odom));
        return s.mb.obstacles_avoided() > 0;
      },
      6000));
  EXPECT_GT(min_clearance, 0.25);
  const Vec2 end = to_robot(frame, Vec2(s.pose.x, s.pose.y));  // on the new stretch, beyond
  EXPECT_LT(std::fabs(end.y()), 0.05);
  EXPECT_GT(end.x(), 1.4 + 0.25);
  EXPECT_NEAR(s.pose.yaw, h, s.cfg.align_tolerance_rad + 0.01);
  EXPECT_TRUE(s.faults.empty());
}

TEST(LineBehaviorAvoidTest, NoRoomEitherSideFaultsPathBlocked) {
  Sim s(true);
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  add_wall(s.world, {-1.0, 1.3}, {6.0, 1.3});  // 0.8 m beside the box: less than 1.1 m needed
  add_wall(s.world, {-1.0, -1.3}, {6.0, -1.3});
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::Fault, 1000));
  EXPECT_TRUE(s.mb.bypass().blocked);
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], Fault::PathBlocked);
  EXPECT_EQ(avoid_phases(s), Phases({"stop", "align", "stopped"}));
  for (int i = 0; i < 50; ++i) {
    s.step();
    expect_still(s.out.twist);
  }
  EXPECT_EQ(s.faults.size(), 1U);
}

TEST(LineBehaviorAvoidTest, ObstacleGoneBeforePlanningFollowsAgain) {
  Sim s(true);
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::Avoid, 1000));
  s.world.clear();  // it walked away
  ASSERT_TRUE(s.run_until_state(LineState::Follow, 10));
  EXPECT_STREQ(s.mb.phase(), "track");
  EXPECT_FALSE(s.mb.bypass().ok);
  EXPECT_FALSE(s.mb.bypass().blocked);
  EXPECT_EQ(s.mb.obstacles_avoided(), 0U);
  EXPECT_EQ(avoid_phases(s), Phases({"stop", "align", "track"}));
  for (int i = 0; i < 50; ++i) s.step();
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_GT(s.out.twist.vx, 0.0);
}

struct BypassRun {
  std::vector<Pose2> poses;  // every AVOID tick's input pose after planning
  double min_clearance = 1e9;
  Pose2 at_min;  // where it was
  double max_yaw_dev = 0.0;
  double x_far_at_plan = 0.0;
  bool rejoin_clear_map = false;
};

// Runs from START to the end of the bypass (obstacles_avoided == 1).
BypassRun run_bypass(Sim& s) {
  BypassRun r;
  s.start_on_tape();
  bool planned = false;
  const bool done = s.run_until(
      [&] {
        if (s.mb.state() == LineState::Avoid && std::string(s.mb.phase()) != "stop" &&
            std::string(s.mb.phase()) != "align") {
          if (!planned) r.x_far_at_plan = s.mb.bypass().x_far;
          planned = true;
          r.poses.push_back(s.pose);
          const double c = s.field.clearance_m(s.last_in.odom);
          if (c < r.min_clearance) {
            r.min_clearance = c;
            r.at_min = s.last_in.odom;
          }
          r.max_yaw_dev = std::fmax(r.max_yaw_dev, std::fabs(wrap_angle(s.pose.yaw)));
        }
        if (s.mb.obstacles_avoided() > 0) r.rejoin_clear_map = s.out.clear_map;
        return s.mb.obstacles_avoided() > 0 || s.mb.state() == LineState::Fault;
      },
      8000);
  EXPECT_TRUE(done);
  return r;
}

// The index of the first pose within `tol` of `p`, or -1.
int first_visit(const std::vector<Pose2>& poses, const Vec2& p, double tol) {
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if ((Vec2(poses[i].x, poses[i].y) - p).norm() < tol) return int(i);
  }
  return -1;
}

class LineBehaviorAvoidBypass : public testing::TestWithParam<bool> {};

TEST_P(LineBehaviorAvoidBypass, PassesTheBoxAndRejoinsTheTape) {
  const bool holo = GetParam();
  Sim s(holo);
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  const BypassRun r = run_bypass(s);
  ASSERT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_STREQ(s.mb.phase(), "track");
  EXPECT_EQ(s.mb.obstacles_avoided(), 1U);
  EXPECT_TRUE(r.rejoin_clear_map);
  EXPECT_TRUE(s.faults.empty());
  EXPECT_EQ(avoid_phases(s), Phases({"stop", "align", "bypass", "rejoin", "track"}));

  const BypassPlan& p = s.mb.bypass();
  ASSERT_TRUE(p.ok);
  EXPECT_NEAR(std::fabs(p.lateral), 0.5 + 0.3 + 0.25, 0.01);
  ASSERT_EQ(p.waypoints.size(), 3U);
  int prev = -1;
  for (std::size_t i = 0; i < p.waypoints.size(); ++i) {
    const int at = first_visit(r.poses, p.waypoints[i], 0.045);
    EXPECT_GT(at, prev) << "waypoint " << i << " not reached after waypoint " << i - 1;
    prev = at;
  }
  // Clearance kept while passing (less the 4 cm within which a waypoint counts as reached: the
  // robot heads for the next one from there); past the box and back on the tape, facing along it.
  EXPECT_GT(r.min_clearance, 0.25)
      << "at " << r.at_min.x << ", " << r.at_min.y << ", " << r.at_min.yaw;
  EXPECT_GT(s.pose.x, 3.0 + 0.25);
  EXPECT_LT(std::fabs(s.pose.y), 0.05);
  EXPECT_LT(std::fabs(s.pose.yaw), s.cfg.align_tolerance_rad + 0.01);
  if (holo) {
    EXPECT_LT(r.max_yaw_dev, 0.01);  // holds the tape heading throughout
    EXPECT_EQ(std::count(s.phases.begin(), s.phases.end(), "rejoin"), 1);
  }
  // Following on, the box behind does not trigger again.
  for (int i = 0; i < 300; ++i) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Follow);
  }
  EXPECT_EQ(s.mb.obstacles_avoided(), 1U);
}

TEST_P(LineBehaviorAvoidBypass, RefinesThePlanWhenTheBoxTurnsOutDeeper) {
  const bool holo = GetParam();
  Sim s(holo);
  add_box(s.world, 2.0, 4.0, -0.5, 0.5);  // 2 m deep: the first view assumes 1 m
  const BypassRun r = run_bypass(s);
  ASSERT_EQ(s.mb.obstacles_avoided(), 1U);
  EXPECT_NEAR(r.x_far_at_plan - s.mb.bypass().x_near, 1.0, 0.02);
  // Tape frame origin is on the tape at the stop point; x_far is along the tape from there.
  const double stop_x = s.mb.bypass().origin.x();
  EXPECT_NEAR(stop_x + s.mb.bypass().x_far, 4.0, 0.03);
  const Vec2 wp1 = s.mb.bypass().waypoints[1];
  EXPECT_NEAR(wp1.x(), 4.0 + 0.3 + 0.25, 0.03);
  EXPECT_GT(r.min_clearance, 0.25)
      << "at " << r.at_min.x << ", " << r.at_min.y << ", " << r.at_min.yaw;
  EXPECT_GT(s.pose.x, 4.0 + 0.25);
  EXPECT_TRUE(s.faults.empty());
}

TEST_P(LineBehaviorAvoidBypass, MovesTheLaneOutWhenTheBoxWidensBehindItsFront) {
  Sim s(GetParam());
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  add_box(s.world, 3.0, 3.6, -0.5, 0.62);  // hidden behind the front from the stop point
  const BypassRun r = run_bypass(s);
  ASSERT_EQ(s.mb.obstacles_avoided(), 1U);
  EXPECT_NEAR(s.mb.bypass().lateral, 0.62 + 0.3 + 0.25, 0.01);
  EXPECT_GT(r.min_clearance, 0.25) << "at " << r.at_min.x << ", " << r.at_min.y;
  EXPECT_GT(s.pose.x, 3.6 + 0.25);
  EXPECT_TRUE(s.faults.empty());
}

INSTANTIATE_TEST_SUITE_P(Drive, LineBehaviorAvoidBypass, testing::Values(true, false),
                         [](const auto& i) { return i.param ? "Holonomic" : "Differential"; });

// Runs until the bypass has started and moved a little; returns the bypass side (+1 left).
int into_bypass(Sim& s) {
  add_box(s.world, 2.0, 3.0, -0.5, 0.5);
  s.start_on_tape();
  EXPECT_TRUE(s.run_until_phase("bypass", 1000));
  for (int i = 0; i < 10; ++i) s.step();
  return s.mb.bypass().side;
}

TEST(LineBehaviorAvoidTest, SomethingAgainstTheBodyStopsThenFaults) {
  Sim s(true);
  const int side = into_bypass(s);
  ASSERT_NE(side, 0);
  // A pole 2 cm from the body, on the side the robot is moving to.
  const double y = s.pose.y + side * (0.25 + 0.02);
  const double y2 = y + side * 0.03;
  add_box(s.world, s.pose.x - 0.015, s.pose.x + 0.015, std::fmin(y, y2), std::fmax(y, y2));
  const Pose2 at = s.pose;
  double t0 = -1.0;
  ASSERT_TRUE(s.run_until(
      [&] {
        if (t0 < 0) t0 = s.last_in.t_s;
        if (s.mb.state() == LineState::Avoid) expect_still(s.out.twist);
        return s.mb.state() == LineState::Fault;
      },
      1000));
  EXPECT_LT(s.field.clearance_m(s.last_in.odom), s.cfg.avoid.emergency_m);
  EXPECT_NEAR(s.last_in.t_s - t0, s.cfg.avoid.blocked_timeout_s, 0.015);
  EXPECT_EQ(s.pose.x, at.x);
  EXPECT_EQ(s.pose.y, at.y);
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], Fault::PathBlocked);
  EXPECT_STREQ(s.mb.phase(), "stopped");
}

TEST(LineBehaviorAvoidTest, SomethingAgainstTheBodyThatLeavesLetsTheBypassGoOn) {
  Sim s(true);
  const int side = into_bypass(s);
  const double y = s.pose.y + side * (0.25 + 0.02);
  const double y2 = y + side * 0.03;
  add_box(s.world, s.pose.x - 0.015, s.pose.x + 0.015, std::fmin(y, y2), std::fmax(y, y2));
  for (int i = 0; i < 200; ++i) {  // 2 s, under blocked_timeout_s
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Avoid);
    expect_still(s.out.twist);
  }
  s.world.resize(4);  // the pole goes; the box stays
  s.step();
  EXPECT_NE(std::hypot(s.out.twist.vx, s.out.twist.vy), 0.0);
  // A second, shorter blockage: the timer restarted, so no fault.
  const std::size_t box_only = s.world.size();
  add_box(s.world, s.pose.x - 0.015, s.pose.x + 0.015, std::fmin(y, y2), std::fmax(y, y2));
  for (int i = 0; i < 200; ++i) s.step();
  EXPECT_EQ(s.mb.state(), LineState::Avoid);
  s.world.resize(box_only);
  ASSERT_TRUE(s.run_until([&] { return s.mb.obstacles_avoided() > 0; }, 6000));
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_TRUE(s.faults.empty());
}

}  // namespace
}  // namespace carril::fw
