// WaypointMission on a cluttered test costmap (round posts, inflated as the firmware does) with
// a robot that integrates the commanded twist on a unicycle: the targets are reached in order,
// lap after lap, without the robot's centre ever on a lethal cell; a target in an obstacle ends
// in a defined fault (or is skipped); update() never allocates.
#include "firmware/mission/WaypointMission.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "host_sim/alloc/AllocCounter.hpp"
#include "tests/unit/mission/WaypointHarness.hpp"

namespace carril::fw {
namespace {

using test_waypoints::Bench;
using test_waypoints::counter;

// The course: a 4 x 4 m square of targets from the start (0, 0), a post just beside each side's
// middle and more scattered round and inside it.
struct Course : Bench {
  Course() {
    for (const Vec2& t : {Vec2(4.0, 0.0), Vec2(4.0, 4.0), Vec2(0.0, 4.0), Vec2(0.0, 0.0)}) {
      cfg.targets.push_back(t);
    }
    for (const Vec2& p : {Vec2(2.0, 0.15), Vec2(4.15, 2.0), Vec2(2.0, 3.8), Vec2(-0.2, 2.0),
                          Vec2(1.0, -0.9), Vec2(3.0, 1.0), Vec2(2.0, 2.0), Vec2(1.0, 3.0),
                          Vec2(3.2, 4.9), Vec2(5.0, 3.0), Vec2(-1.0, 1.0), Vec2(3.0, -0.7)}) {
      costmap.post(p.x(), p.y());
    }
  }
};

TEST(WaypointMissionTest, TwoLapsOfTheCourseInOrderWithoutTouching) {
  Course c;
  c.cfg.laps = 2;
  ASSERT_TRUE(c.cfg.validate()) << c.cfg.validate().message();
  c.start();
  c.run(300.0);
  ASSERT_EQ(c.mission->current(), WaypointMission::State::Done);
  EXPECT_EQ(c.mission->targets_reached(), 8u);
  EXPECT_EQ(c.mission->targets_skipped(), 0u);
  EXPECT_EQ(c.mission->laps_done(), 2u);
  EXPECT_EQ(c.order, (std::vector<std::size_t>{0, 1, 2, 3, 0, 1, 2, 3}));
  for (double miss : c.reach_miss) EXPECT_LE(miss, c.cfg.reach_radius_m);
  EXPECT_FALSE(c.on_lethal);
  EXPECT_GT(c.min_clearance, 0.2);  // the body's half width less 5 cm
  // Lap times: 16 m at no more than 0.4 m/s, so at least 40 s; both laps run from (0, 0).
  ASSERT_EQ(c.mission->lap_times().size(), 2u);
  const double lap1 = c.mission->lap_times()[0], lap2 = c.mission->lap_times()[1];
  EXPECT_GT(lap1, 40.0);
  EXPECT_LT(lap1, 100.0);
  EXPECT_NEAR(lap2, lap1, 0.2 * lap1);
  EXPECT_NEAR(lap1 + lap2, c.t_s(), 0.05);  // the laps cover the whole run after WAIT
  EXPECT_EQ(counter(*c.mission, "laps"), 2u);
  EXPECT_EQ(counter(*c.mission, "targets_reached"), 8u);
  EXPECT_EQ(counter(*c.mission, "last_lap_ms"), std::uint32_t(std::lround(lap2 * 1000.0)));
  EXPECT_EQ(counter(*c.mission, "best_lap_ms"),
            std::uint32_t(std::lround(std::fmin(lap1, lap2) * 1000.0)));
  std::printf("laps %.2f s, %.2f s; min clearance %.3f m; emergency stops %u, bypasses %u\n", lap1,
              lap2, c.min_clearance, c.mission->emergency_stops(), c.mission->bypasses());
}

// A post right on the line to the target: the pull and the push in line, VFF's local minimum.
// The robot goes round it (bypass) and reaches the target; with bypass off it holds short of the
// post and ends stuck (no_path), never touching it either way.
TEST(WaypointMissionTest, PostOnTheLineIsBypassed) {
  for (bool bypass : {true, false}) {
    SCOPED_TRACE(bypass ? "bypass" : "no bypass");
    Course c;
    c.cfg.targets.clear();
    c.cfg.targets.push_back(Vec2(5.0, 5.0));  // the course's post at (2, 2) is on the way
    c.pose = Pose2{0.0, 0.0, kPi / 4};
    c.cfg.bypass = bypass;
    c.start();
    const MissionOutput out = c.run(60.0);
    EXPECT_FALSE(c.on_lethal);
    EXPECT_GT(c.min_clearance, 0.2);
    if (bypass) {
      EXPECT_EQ(c.mission->current(), WaypointMission::State::Done);
      EXPECT_GE(c.mission->bypasses(), 1u);
      EXPECT_EQ(counter(*c.mission, "bypasses"), c.mission->bypasses());
    } else {
      EXPECT_EQ(out.fault, Fault::NoPath);
      EXPECT_STREQ(c.mission->state().phase, "stuck");
      EXPECT_EQ(c.mission->bypasses(), 0u);
    }
  }
}

TEST(WaypointMissionTest, WaitsForTheDrivesAndTheCostmap) {
  Course c;
  c.drives_ready = false;
  c.start();
  c.run(0.5);
  EXPECT_EQ(c.mission->current(), WaypointMission::State::Wait);
  EXPECT_EQ(c.mission->state().status, MissionStatus::Starting);
  EXPECT_EQ(c.pose.x, 0.0);
  c.drives_ready = true;
  c.run(0.5);
  EXPECT_EQ(c.mission->current(), WaypointMission::State::Drive);
  EXPECT_GT(c.pose.x, 0.0);
}

// A target inside a post the lidar has seen: goal_invalid as soon as it becomes current, the
// robot stopped, the targets before it reached.
TEST(WaypointMissionTest, TargetInAnObstacleSeenByTheLidarIsGoalInvalid) {
  Course c;
  c.cfg.targets[1] = Vec2(3.0, 1.0);  // the post at (3, 1)
  c.start();
  const MissionOutput out = c.run(60.0);
  EXPECT_EQ(out.fault, Fault::GoalInvalid);
  EXPECT_STREQ(c.mission->state().phase, "goal_invalid");
  EXPECT_EQ(c.mission->targets_reached(), 1u);
  EXPECT_EQ(c.mission->target_index(), 1u);
  EXPECT_EQ(out.motion.twist.vx, 0.0);
  EXPECT_EQ(out.motion.twist.wz, 0.0);
}

// Issue 46 item 8: a target inside a wall of the static map is goal_invalid at once, before the
// lidar has seen it, and the robot does not drive at it.
TEST(WaypointMissionTest, TargetInAMappedWallIsGoalInvalidAtOnce) {
  Course c;
  c.costmap.mapped_post(4.0, 1.2);
  c.cfg.targets[0] = Vec2(4.0, 1.2);
  c.start();
  const MissionOutput out = c.run(20.0);
  EXPECT_EQ(out.fault, Fault::GoalInvalid);
  EXPECT_STREQ(c.mission->state().phase, "goal_invalid");
  EXPECT_EQ(c.mission->targets_reached(), 0u);
  EXPECT_LT(c.t_s(), 1.0);
}

// A target inside a post the lidar has not seen (only the map has it): the pull drives the robot
// at it, the emergency stop holds it short, no progress: no_path ("stuck") within stuck_time_s
// of the last progress, long before the target timeout. The centre never on a lethal cell.
TEST(WaypointMissionTest, TargetInAnUnseenObstacleEndsStuckWithinTheTimeout) {
  Course c;
  c.costmap.post(4.0, 1.2, false);
  c.cfg.targets[1] = Vec2(4.0, 1.2);
  c.cfg.stuck_time_s = 5.0;
  c.cfg.target_timeout_s = 60.0;
  c.start();
  const MissionOutput out = c.run(120.0);
  EXPECT_EQ(out.fault, Fault::NoPath);
  EXPECT_STREQ(c.mission->state().phase, "stuck");
  EXPECT_EQ(c.mission->targets_reached(), 1u);
  EXPECT_FALSE(c.on_lethal);
  EXPECT_GT(c.min_clearance, 0.2);
  EXPECT_GE(c.mission->emergency_stops(), 1u);
  EXPECT_LT(c.t_s(), 12.0 + 10.0 + 5.0);  // the first target (~12 s), the approach, stuck_time
}

// The same with on_unreachable = Skip: the target is skipped and counted, the lap goes on.
TEST(WaypointMissionTest, UnreachableTargetSkippedWhenSoConfigured) {
  Course c;
  c.costmap.post(4.0, 1.2, false);
  c.cfg.targets[1] = Vec2(4.0, 1.2);
  c.cfg.stuck_time_s = 5.0;
  c.cfg.on_unreachable = WaypointGiveUp::Skip;
  c.start();
  const MissionOutput out = c.run(300.0);
  EXPECT_EQ(out.fault, Fault::None);
  ASSERT_EQ(c.mission->current(), WaypointMission::State::Done);
  EXPECT_EQ(c.mission->targets_skipped(), 1u);
  EXPECT_EQ(c.mission->targets_reached(), 3u);
  EXPECT_EQ(c.order, (std::vector<std::size_t>{0, 2, 3}));
  EXPECT_EQ(c.mission->laps_done(), 1u);
  EXPECT_EQ(counter(*c.mission, "targets_skipped"), 1u);
  EXPECT_FALSE(c.on_lethal);
  // Reported: a skip, then driving on.
  bool skip_then_drive = false;
  for (std::size_t i = 0; i + 1 < c.phases.size(); ++i)
    skip_then_drive |= c.phases[i] == "skip" && c.phases[i + 1] == "drive";
  EXPECT_TRUE(skip_then_drive) << ::testing::PrintToString(c.phases);
}

// A target not reached within target_timeout_s: no_path ("timeout").
TEST(WaypointMissionTest, TargetTimeoutIsNoPath) {
  Course c;
  c.cfg.target_timeout_s = 3.0;  // the first target is 4 m away: at least 10 s
  c.start();
  const MissionOutput out = c.run(60.0);
  EXPECT_EQ(out.fault, Fault::NoPath);
  EXPECT_STREQ(c.mission->state().phase, "timeout");
  EXPECT_NEAR(c.t_s(), 3.0, 0.05);
}

TEST(WaypointMissionTest, ValidateNamesTheKey) {
  WaypointConfig cfg;
  EXPECT_STREQ(cfg.validate().message(), "waypoints.targets: empty, expected 1 to 32 targets");
  cfg.targets.push_back(Vec2(1.0, 0.0));
  EXPECT_TRUE(cfg.validate());
  cfg.laps = 0;
  EXPECT_STREQ(cfg.validate().message(), "waypoints.laps: 0 laps, expected 1 to 100 laps");
  cfg.laps = 1;
  cfg.speed_mps = 0.03;  // below the follower's min_speed_mps (0.05)
  EXPECT_STREQ(cfg.validate().message(), "vff.min_speed_mps: 0.05 m/s, expected 0 to 0.03 m/s");
  cfg.speed_mps = 0.4;
  cfg.targets.push_back(Vec2(0.0, NAN));
  EXPECT_STREQ(cfg.validate().message(),
               "waypoints.targets[1]: (0, nan) m, expected -1000 to 1000 m");
}

TEST(WaypointMissionTest, UpdateDoesNotAllocate) {
  Course c;
  c.cfg.laps = 2;
  c.costmap.post(5.0, -1.0, false);
  c.cfg.targets.push_back(Vec2(5.0, -1.0));  // unreachable, off the course: skipped once a lap
  c.cfg.on_unreachable = WaypointGiveUp::Skip;
  c.start();
  c.allocations_counted = true;
  const std::uint64_t total_before = alloc::count_total();
  c.run(400.0);
  ASSERT_EQ(c.mission->current(), WaypointMission::State::Done);
  EXPECT_EQ(c.mission->targets_skipped(), 2u) << ::testing::PrintToString(c.order);
  EXPECT_EQ(alloc::count_in_windows(), 0u);
  EXPECT_GT(alloc::count_total(), total_before);  // counting is live (the test's vectors)
}

}  // namespace
}  // namespace carril::fw
