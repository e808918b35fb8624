#include "firmware/control/VffFollower.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

void integrate(Pose2& p, const Twist& t, double dt) {
  p.x += t.vx * std::cos(p.yaw) * dt;
  p.y += t.vx * std::sin(p.yaw) * dt;
  p.yaw = wrap_angle(p.yaw + t.wz * dt);
}

struct BlockRun {
  bool reached = false;
  double min_clearance = 1e9;  // to the block's centre [m]
  double y_at_block = 0.0;     // lateral position when passing x = 2 [m]
  Pose2 end;
  std::uint64_t allocations = 0;  // inside the update loop
};

// Drives the straight path (0,0) -> (4,0) with a 2 x 2-cell block of `block_cost` centred at
// (2.0, -0.2) beside it.
BlockRun drive_past_block(std::uint8_t block_cost, const VffConfig& cfg = {}) {
  RollingGrid<std::uint8_t> map;
  EXPECT_TRUE(map.init(120, 80, 0.05, cost::kFree));
  map.recenter(2.0, 0.0);
  const int bx = map.cell_of(1.975), by = map.cell_of(-0.225);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) map.at(bx + dx, by + dy) = block_cost;
  const std::vector<Vec2> path = {{0.0, 0.0}, {4.0, 0.0}};
  VffFollower f(cfg);
  Pose2 pose{0.0, 0.0, 0.0};
  BlockRun run;
  bool passed = false;
  const auto before = alloc::count_total();
  for (int i = 0; i < 4000 && !f.at_end(); ++i) {
    integrate(pose, f.update(pose, path.data(), path.size(), map), 0.02);
    run.min_clearance = std::fmin(run.min_clearance, std::hypot(pose.x - 2.0, pose.y + 0.2));
    if (!passed && pose.x >= 2.0) {
      passed = true;
      run.y_at_block = pose.y;
    }
  }
  run.allocations = alloc::count_total() - before;
  run.reached = f.at_end();
  run.end = pose;
  return run;
}

TEST(VffFollowerTest, ConfigValidateNamesTheKey) {
  VffConfig cfg;
  EXPECT_TRUE(cfg.validate().is_ok());
  cfg.cost_threshold = 0;
  EXPECT_NE(std::string(cfg.validate().message()).find("vff.cost_threshold"), std::string::npos);
}

TEST(VffFollowerTest, TurnsAwayFromALethalCellBesideThePathAndReachesTheGoal) {
  const BlockRun run = drive_past_block(cost::kLethal);
  EXPECT_EQ(run.allocations, 0u);
  EXPECT_TRUE(run.reached);
  EXPECT_NEAR(run.end.x, 4.0, 0.06);
  EXPECT_NEAR(run.end.y, 0.0, 0.06);
  EXPECT_GT(run.y_at_block, 0.05) << "pushed to the side away from the block";
  EXPECT_GT(run.min_clearance, 0.27);  // 0.2 when driving the path straight
}

TEST(VffFollowerTest, CellsBelowTheThresholdDoNotPush) {
  const BlockRun run = drive_past_block(100);
  EXPECT_TRUE(run.reached);
  EXPECT_LT(std::fabs(run.y_at_block), 0.01);
}

TEST(VffFollowerTest, TurnsOnTheSpotBeforeDrivingAway) {
  RollingGrid<std::uint8_t> map;
  ASSERT_TRUE(map.init(40, 40, 0.05, cost::kFree));
  const std::vector<Vec2> path = {{0.0, 0.0}, {0.0, 3.0}};  // north, robot faces east
  VffFollower f;
  const Twist t = f.update(Pose2{0.0, 0.0, 0.0}, path.data(), path.size(), map);
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_GT(t.wz, 0.5);
  EXPECT_GT(f.attraction().y(), 0.9);
}

TEST(VffFollowerTest, NonFinitePoseGivesZeroTwist) {
  RollingGrid<std::uint8_t> map;
  ASSERT_TRUE(map.init(40, 40, 0.05, cost::kFree));
  const std::vector<Vec2> path = {{0.0, 0.0}, {2.0, 0.0}};
  VffFollower f;
  const Twist t = f.update(Pose2{0.0, std::nan(""), 0.0}, path.data(), path.size(), map);
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_EQ(t.wz, 0.0);
}

}  // namespace
}  // namespace carril::fw
