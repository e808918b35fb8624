#include "firmware/control/PurePursuitFollower.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

// Unicycle integration of a body twist over dt [s].
void integrate(Pose2& p, const Twist& t, double dt) {
  p.x += t.vx * std::cos(p.yaw) * dt;
  p.y += t.vx * std::sin(p.yaw) * dt;
  p.yaw = wrap_angle(p.yaw + t.wz * dt);
}

TEST(PurePursuitFollowerTest, ConfigValidateNamesTheKey) {
  PurePursuitConfig cfg;
  EXPECT_TRUE(cfg.validate().is_ok());
  cfg.lookahead_m = 0.0;
  EXPECT_NE(std::string(cfg.validate().message()).find("pure_pursuit.lookahead_m"),
            std::string::npos);
}

TEST(PurePursuitFollowerTest, ConvergesOntoAStraightLineFromAnOffset) {
  const std::vector<Vec2> path = {{0.0, 0.0}, {3.0, 0.0}, {8.0, 0.0}};
  PurePursuitFollower f;
  Pose2 pose{0.0, 0.5, 0.0};
  double worst_after_4m = 0.0;
  int steps = 0;
  const auto before = alloc::count_total();
  for (; steps < 3000 && !f.at_end(); ++steps) {
    integrate(pose, f.update(pose, path.data(), path.size()), 0.02);
    if (pose.x > 4.0) worst_after_4m = std::fmax(worst_after_4m, std::fabs(pose.y));
  }
  EXPECT_EQ(alloc::count_total(), before);
  EXPECT_TRUE(f.at_end());
  EXPECT_LT(worst_after_4m, 0.02);
  EXPECT_NEAR(pose.x, 8.0, 0.06);
  EXPECT_EQ(f.progress(), 1u);
  const Twist stopped = f.update(pose, path.data(), path.size());
  EXPECT_EQ(stopped.vx, 0.0);
  EXPECT_EQ(stopped.wz, 0.0);
}

TEST(PurePursuitFollowerTest, KeepsCrossTrackSmallOnACircle) {
  std::vector<Vec2> path;
  const double r = 2.0;
  for (int i = 0; i <= 300; ++i) {
    const double a = -kPi / 2 + 1.9 * kPi * i / 300.0;  // almost a full turn, counter-clockwise
    path.push_back({r * std::cos(a), r * std::sin(a) + r});
  }
  PurePursuitConfig cfg;
  cfg.lookahead_m = 0.4;
  PurePursuitFollower f(cfg);
  Pose2 pose{0.0, 0.0, 0.0};  // on the circle, tangent
  double worst = 0.0;
  for (int i = 0; i < 5000 && !f.at_end(); ++i) {
    integrate(pose, f.update(pose, path.data(), path.size()), 0.02);
    const double e = std::fabs(std::hypot(pose.x, pose.y - r) - r);
    worst = std::fmax(worst, e);
  }
  EXPECT_TRUE(f.at_end());
  // Pure pursuit cuts inside a circle by about L^2 / (2 R) = 0.04 m.
  EXPECT_LT(worst, 0.05);
}

TEST(PurePursuitFollowerTest, TurnsOnTheSpotWhenThePathIsBehind) {
  const std::vector<Vec2> path = {{0.0, 0.0}, {-2.0, 0.0}};
  PurePursuitFollower f;
  const Twist t = f.update(Pose2{0.0, 0.0, 0.0}, path.data(), path.size());
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_GT(std::fabs(t.wz), 0.5);
}

TEST(PurePursuitFollowerTest, NonFinitePoseGivesZeroTwist) {
  const std::vector<Vec2> path = {{0.0, 0.0}, {2.0, 0.0}};
  PurePursuitFollower f;
  const Twist t = f.update(Pose2{std::nan(""), 0.0, 0.0}, path.data(), path.size());
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_EQ(t.wz, 0.0);
  EXPECT_EQ(f.update(Pose2{}, path.data(), 0).vx, 0.0);
}

}  // namespace
}  // namespace carril::fw
