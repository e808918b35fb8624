// GotoMission through a sequence of goals (the taxi) on a city grid of blocks: a costmap window
// that never moves (a mapped town, its lower-left corner not at the robot) and a robot that moves
// exactly as commanded. Goals are reached in order and counted, a street blocked after the first
// plan is driven round by another street, a goal in a block ends in goal_invalid with a safe
// stop, and update() never allocates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/GotoMission.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

// The master and the lidar layer as two windows placed by the test (neither follows the robot).
class CityCostmap final : public CostmapView {
 public:
  // Both windows over [x0, x0 + n * 0.05) x [y0, y0 + n * 0.05) [m].
  CityCostmap(double x0, double y0, int n) {
    master_.init(n, n, kRes, cost::kFree);
    master_.move_origin(master_.cell_of(x0), master_.cell_of(y0));
    lidar_window(x0, y0, n);
  }
  // Places the lidar layer's window (cleared) [m, m, cells].
  void lidar_window(double x0, double y0, int n) {
    obstacles_.init(n, n, kRes, cost::kUnknown);
    obstacles_.move_origin(obstacles_.cell_of(x0), obstacles_.cell_of(y0));
  }
  const RollingGrid<std::uint8_t>& master() const override { return master_; }
  const RollingGrid<std::uint8_t>& obstacles() const override { return obstacles_; }
  std::uint32_t updates() const override { return updates_; }
  RollingGrid<std::uint8_t>& master_grid() { return master_; }
  RollingGrid<std::uint8_t>& lidar_grid() { return obstacles_; }
  void touch() { ++updates_; }

  // A lethal rectangle [x0, x1] x [y0, y1] [m], inflated as the firmware does: inscribed (253)
  // within 0.25 m, then 252 exp(-10 (d - 0.25)) out to 0.55 m. seen_by_lidar: lethal in the
  // lidar layer too (where its window reaches).
  void block(double x0, double y0, double x1, double y1, bool seen_by_lidar = false) {
    for (int cy = master_.origin_cy(); cy < master_.origin_cy() + master_.ny(); ++cy) {
      for (int cx = master_.origin_cx(); cx < master_.origin_cx() + master_.nx(); ++cx) {
        const double x = master_.center_of(cx), y = master_.center_of(cy);
        const double dx = std::fmax(0.0, std::fmax(x0 - x, x - x1));
        const double dy = std::fmax(0.0, std::fmax(y0 - y, y - y1));
        const double d = std::hypot(dx, dy);
        std::uint8_t& c = master_.at(cx, cy);
        if (d == 0.0) {
          c = cost::kLethal;
          if (seen_by_lidar && obstacles_.contains(cx, cy)) obstacles_.at(cx, cy) = cost::kLethal;
        } else if (d <= 0.25 && c != cost::kLethal) {
          c = cost::kInscribed;
        } else if (d <= 0.55 && cost::passable(c)) {
          const auto v = static_cast<std::uint8_t>(252.0 * std::exp(-10.0 * (d - 0.25)));
          if (v > c) c = v;
        }
      }
    }
    ++updates_;
  }

  // The town: streets 1 m wide along x, y = 0..1, 3..4, 6..7 between four 2 x 2 m blocks, a
  // wall round the outside (0.2 m thick, just beyond the outer streets).
  void build_town() {
    for (double a : {1.0, 4.0})
      for (double b : {1.0, 4.0}) block(a, b, a + 2.0, b + 2.0, true);
    block(-0.2, -0.2, 7.2, 0.0, true);
    block(-0.2, 7.0, 7.2, 7.2, true);
    block(-0.2, -0.2, 0.0, 7.2, true);
    block(7.0, -0.2, 7.2, 7.2, true);
  }

 private:
  static constexpr double kRes = 0.05;
  RollingGrid<std::uint8_t> master_, obstacles_;
  std::uint32_t updates_ = 0;
};

// The window: 8 x 8 m from (-0.5, -0.5); the robot starts at the town's corner (0.5, 0.5).
struct Taxi {
  Taxi() : costmap(-0.5, -0.5, 160) { costmap.build_town(); }

  GotoConfig cfg;
  Topic<OdometryMsg> odom;
  CityCostmap costmap;
  Topic<CostmapMsg> costmap_topic{CostmapMsg{&costmap}};  // the bus's costmap topic
  std::unique_ptr<GotoMission> mission;
  Pose2 pose{0.5, 0.5, 0.0};
  int tick = 0;
  bool touched = false;           // the centre on an inscribed or lethal cell (body on a block)
  std::vector<Pose2> reached_at;  // the pose whenever goals_reached went up
  std::vector<GotoMission::State> states;  // every state change
  double max_y_before_x5 = -1e9;           // how far north the robot went before passing x = 5 [m]
  bool allocations_counted = false;        // update() inside an allocation window

  void start() {
    mission = std::make_unique<GotoMission>(cfg, Footprint{0.25, 0.25}, false, odom, costmap_topic);
    mission->enter(MissionContext{});
  }
  // Runs until done or failed or `seconds` pass; the robot follows the twist.
  MissionOutput run(double seconds) {
    MissionOutput out;
    for (int i = 0; i < int(seconds * 100); ++i, ++tick) {
      odom.publish(OdometryMsg{pose, {}}, tick);
      MissionContext ctx;
      ctx.t_s = tick * 0.01;
      ctx.dt_s = 0.01;
      ctx.drives_ready = true;
      const std::uint32_t before = mission->goals_reached();
      if (allocations_counted) alloc::begin_window();
      out = mission->update(ctx);
      if (allocations_counted) alloc::end_window();
      if (mission->goals_reached() != before) reached_at.push_back(pose);
      if (states.empty() || states.back() != mission->current()) {
        states.push_back(mission->current());
      }
      const MissionStatus s = mission->state().status;
      if (s == MissionStatus::Done || s == MissionStatus::Failed) break;
      const Twist& t = out.motion.twist;
      pose.x += std::cos(pose.yaw) * t.vx * 0.01;
      pose.y += std::sin(pose.yaw) * t.vx * 0.01;
      pose.yaw = wrap_angle(pose.yaw + t.wz * 0.01);
      int cx = 0, cy = 0;
      if (costmap.master().world_to_cell(pose.x, pose.y, cx, cy) &&
          !cost::passable(costmap.master().at(cx, cy))) {
        touched = true;
      }
      if (pose.x < 5.0) max_y_before_x5 = std::fmax(max_y_before_x5, pose.y);
    }
    return out;
  }
};

const Pose2 kCorner1{6.5, 0.5, kPi / 2}, kCorner2{6.5, 6.5, kPi}, kCorner3{0.5, 6.5, -kPi / 2};

TEST(GotoSequenceTest, ThreeGoalsReachedInOrder) {
  Taxi t;
  for (const Pose2& g : {kCorner1, kCorner2, kCorner3}) t.cfg.goals.push_back(g);
  ASSERT_TRUE(t.cfg.validate()) << t.cfg.validate().message();
  t.start();
  EXPECT_EQ(t.mission->goal_index(), 0u);
  t.run(200.0);
  ASSERT_EQ(t.mission->current(), GotoMission::State::Done);
  EXPECT_EQ(t.mission->goals_reached(), 3u);
  EXPECT_EQ(t.mission->goal_index(), 2u);
  ASSERT_EQ(t.reached_at.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const Pose2& g = t.cfg.goals[k];
    const Pose2& p = t.reached_at[k];
    EXPECT_LT(std::hypot(p.x - g.x, p.y - g.y), 0.1) << "goal " << k;
    EXPECT_LT(std::fabs(wrap_angle(p.yaw - g.yaw)), 0.1) << "goal " << k;
  }
  EXPECT_FALSE(t.touched);
  MissionCounters c;
  t.mission->counters(c);
  ASSERT_EQ(c.size(), 7u);
  EXPECT_STREQ(c[3].name, "goals_reached");
  EXPECT_EQ(c[3].value, 3u);
  EXPECT_EQ(c[0].value, 3u);  // one plan per goal
  EXPECT_STREQ(c[4].name, "vff_fallbacks");
  EXPECT_EQ(c[4].value, 0u);  // pure pursuit: VFF never drove
  EXPECT_STREQ(c[5].name, "corner_turns");
  EXPECT_STREQ(c[6].name, "corner_escapes");
}

// With align_every_goal off, only the last goal is turned to: no ALIGN before it.
TEST(GotoSequenceTest, IntermediateGoalsNotAlignedWhenSoConfigured) {
  Taxi t;
  for (const Pose2& g : {kCorner1, kCorner2}) t.cfg.goals.push_back(g);
  t.cfg.align_every_goal = false;
  t.start();
  t.run(150.0);
  ASSERT_EQ(t.mission->current(), GotoMission::State::Done);
  EXPECT_EQ(t.mission->goals_reached(), 2u);
  int aligns = 0;
  for (GotoMission::State s : t.states) aligns += s == GotoMission::State::Align;
  EXPECT_EQ(aligns, 1);
  ASSERT_EQ(t.reached_at.size(), 2u);
  EXPECT_LT(std::hypot(t.reached_at[0].x - kCorner1.x, t.reached_at[0].y - kCorner1.y), 0.1);
  // Reached on arrival, still facing east (not turned to the goal's north).
  EXPECT_GT(std::fabs(wrap_angle(t.reached_at[0].yaw - kCorner1.yaw)), 0.5);
}

// The south street is blocked between x = 4.5 and 5.5 (an obstacle not on the map) once the
// first plan runs along it: the taxi replans before reaching it (no emergency stop) and takes
// the middle street north, the middle east-west street and the east street south.
TEST(GotoSequenceTest, ReplansRoundABlockedStreetViaAnother) {
  Taxi t;
  t.cfg.goals.push_back(kCorner1);
  t.cfg.goals.push_back(kCorner2);
  t.start();
  t.run(2.0);
  ASSERT_EQ(t.mission->current(), GotoMission::State::Follow);
  ASSERT_LT(t.pose.x, 1.5);
  const double path_max_y = [&] {
    double m = -1e9;
    for (const Vec2& p : t.mission->path()) m = std::fmax(m, p.y());
    return m;
  }();
  EXPECT_LT(path_max_y, 1.0);  // the first plan: along the south street
  t.costmap.block(4.5, 0.0, 5.5, 1.0, true);
  t.run(200.0);
  ASSERT_EQ(t.mission->current(), GotoMission::State::Done);
  EXPECT_EQ(t.mission->goals_reached(), 2u);
  EXPECT_GE(t.mission->replans(), 1u);
  EXPECT_GT(t.max_y_before_x5, 3.0);  // north by the middle street before passing x = 5
  EXPECT_FALSE(t.touched);
  MissionCounters c;
  t.mission->counters(c);
  EXPECT_EQ(c[2].value, 0u);  // no emergency stop: the replan came before the block
}

// The second goal lies in a block: the first is reached, then goal_invalid and a zero twist.
TEST(GotoSequenceTest, GoalInAWallFailsGoalInvalid) {
  Taxi t;
  t.cfg.goals.push_back(kCorner1);
  t.cfg.goals.push_back(Pose2{5.0, 2.0, 0.0});  // inside the block [4, 6] x [1, 3]
  t.cfg.goals.push_back(kCorner3);
  t.start();
  const MissionOutput out = t.run(100.0);
  EXPECT_EQ(out.fault, Fault::GoalInvalid);
  EXPECT_EQ(t.mission->state().status, MissionStatus::Failed);
  EXPECT_EQ(t.mission->goals_reached(), 1u);
  EXPECT_EQ(t.mission->goal_index(), 1u);
  EXPECT_EQ(out.motion.twist.vx, 0.0);
  EXPECT_EQ(out.motion.twist.wz, 0.0);
  // Asked again, it stays failed and stopped.
  const MissionOutput again = t.run(0.01);
  EXPECT_EQ(again.fault, Fault::GoalInvalid);
  EXPECT_EQ(again.motion.twist.vx, 0.0);
}

// The lidar layer is a small window that does not reach the goal; a cell of it aliases (in its
// circular storage) the goal's cell and is lethal. The map shows the goal in a lethal patch (the
// terrain's look from afar) that the goal area opens: the planner must not read the lidar
// window outside its bounds (it would see the aliased obstacle and keep the goal closed).
TEST(GotoSequenceTest, GoalAreaOpensWhereTheLidarWindowDoesNotReach) {
  Taxi t;
  // 40 x 40 cells from (-0.5, -0.5): the goal's cell (70, 10) aliases (-10, 10) in storage.
  t.costmap.lidar_window(-0.5, -0.5, 40);
  RollingGrid<std::uint8_t>& lidar = t.costmap.lidar_grid();
  for (int cy = 4; cy <= 16; ++cy)
    for (int cx = -10; cx <= -4; ++cx) lidar.at(cx, cy) = cost::kLethal;
  // The terrain patch in the master round the goal (3.525, 0.525), not seen by the lidar.
  RollingGrid<std::uint8_t>& m = t.costmap.master_grid();
  for (int cy = 8; cy <= 12; ++cy)
    for (int cx = 68; cx <= 72; ++cx) m.at(cx, cy) = cost::kLethal;
  t.costmap.touch();
  t.cfg.goal = Pose2{3.525, 0.525, 0.0};
  t.start();
  const MissionOutput out = t.run(60.0);
  EXPECT_EQ(out.fault, Fault::None);
  EXPECT_EQ(t.mission->current(), GotoMission::State::Done);
  EXPECT_EQ(t.mission->goals_reached(), 1u);
}

TEST(GotoSequenceTest, ValidateNamesTheBadGoal) {
  GotoConfig cfg;
  cfg.goals.push_back(kCorner1);
  cfg.goals.push_back(Pose2{2000.0, 0.0, 0.0});
  const Status s = cfg.validate();
  ASSERT_FALSE(s);
  EXPECT_STREQ(s.message(), "goto.goals[1].x: 2000 m, expected -1000 to 1000 m");
  cfg.goals[1] = Pose2{1.0, 0.0, 9.0};
  EXPECT_STREQ(cfg.validate().message(),
               "goto.goals[1].yaw: 9 rad, expected -6.28319 to 6.28319 rad");
  cfg.goals[1] = Pose2{NAN, 0.0, 0.0};  // quiet: no FP trap
  EXPECT_STREQ(cfg.validate().message(), "goto.goals[1].x: nan m, expected -1000 to 1000 m");
  cfg.goals[1].x = 1.0;
  EXPECT_TRUE(cfg.validate());
}

TEST(GotoSequenceTest, UpdateDoesNotAllocate) {
  Taxi t;
  for (const Pose2& g : {kCorner1, kCorner2, kCorner3}) t.cfg.goals.push_back(g);
  t.start();
  t.run(2.0);
  t.costmap.block(4.5, 0.0, 5.5, 1.0, true);  // a replan on the way
  t.allocations_counted = true;
  const std::uint64_t total_before = alloc::count_total();
  t.run(250.0);
  ASSERT_EQ(t.mission->current(), GotoMission::State::Done);
  EXPECT_GE(t.mission->replans(), 1u);
  EXPECT_EQ(alloc::count_in_windows(), 0u);
  EXPECT_GT(alloc::count_total(), total_before);  // counting is live (the test's vectors)
}

}  // namespace
}  // namespace carril::fw
