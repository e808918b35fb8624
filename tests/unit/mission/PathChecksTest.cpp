// The path followers' shared checks: the path ahead, and emergency stops in a row.
#include "firmware/mission/PathChecks.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace carril::fw {
namespace {

// An L-shaped path from the robot at the origin: 2 m along x, then 2 m along y.
const Vec2 kPath[] = {Vec2(1.0, 0.0), Vec2(2.0, 0.0), Vec2(2.0, 2.0)};

TEST(PathChecks, APathIsBlockedOnlyWithinTheLookaheadAndBeyondTheRobotsOwnCell) {
  const Pose2 robot{0.0, 0.0, 0.0};
  const auto near = [](const Vec2& at) {
    return [at](const Vec2& p) { return (p - at).norm() < 0.06; };
  };
  // Something on the second leg, 1 m past the corner: 3 m along the path.
  EXPECT_TRUE(path_blocked_ahead(robot, kPath, 3, 0, 3.0, 0.05, 0.25, near(Vec2(2.0, 1.0))));
  // A segment begun within the lookahead is checked whole; one begun beyond it is not.
  // (The second leg begins 2 m along the path.)
  EXPECT_TRUE(path_blocked_ahead(robot, kPath, 3, 0, 2.1, 0.05, 0.25, near(Vec2(2.0, 1.0))));
  EXPECT_FALSE(path_blocked_ahead(robot, kPath, 3, 0, 1.9, 0.05, 0.25, near(Vec2(2.0, 1.0))));
  // Starting further along the path skips the waypoints behind.
  EXPECT_FALSE(path_blocked_ahead(robot, kPath, 3, 2, 3.0, 0.05, 0.25, near(Vec2(1.5, 0.0))));
  // Within own_radius_m of the robot is its own cell.
  EXPECT_FALSE(path_blocked_ahead(robot, kPath, 3, 0, 3.0, 0.05, 0.25, near(Vec2(0.2, 0.0))));
  EXPECT_TRUE(path_blocked_ahead(robot, kPath, 3, 0, 3.0, 0.05, 0.1, near(Vec2(0.2, 0.0))));
  // Nothing in the way, or no path at all.
  EXPECT_FALSE(path_blocked_ahead(robot, kPath, 3, 0, 10.0, 0.05, 0.25, near(Vec2(5.0, 5.0))));
  EXPECT_FALSE(path_blocked_ahead(robot, kPath, 0, 0, 10.0, 0.05, 0.25, near(Vec2(1.0, 0.0))));
}

TEST(PathChecks, APathIsSampledAtLeastEveryStep) {
  std::vector<Vec2> seen;
  const Pose2 robot{0.0, 0.0, 0.0};
  path_blocked_ahead(robot, kPath, 3, 0, 10.0, 0.3, 0.0, [&](const Vec2& p) {
    seen.push_back(p);
    return false;
  });
  ASSERT_FALSE(seen.empty());
  Vec2 last(0.0, 0.0);
  for (const Vec2& p : seen) {
    EXPECT_LE((p - last).norm(), 0.3 + 1e-12);
    last = p;
  }
  EXPECT_NEAR((seen.back() - Vec2(2.0, 2.0)).norm(), 0.0, 1e-12);  // to the path's end
}

TEST(PathChecks, StopsInARowWithoutProgressEndTheTarget) {
  StopStreak s;
  const Vec2 here(1.0, 1.0);
  EXPECT_FALSE(s.too_many(here, 0.4, 2));
  EXPECT_FALSE(s.too_many(here + Vec2(0.1, 0.0), 0.4, 2));
  EXPECT_TRUE(s.too_many(here, 0.4, 2));  // the third stop in a row within 0.4 m
  EXPECT_EQ(s.count(), 3u);
  // Getting somewhere between two stops starts a new streak.
  EXPECT_FALSE(s.too_many(here + Vec2(1.0, 0.0), 0.4, 2));
  EXPECT_EQ(s.count(), 1u);
  s.reset();
  EXPECT_EQ(s.count(), 0u);
  EXPECT_TRUE(s.too_many(here, 0.4, 0));  // max 0: the first stop gives up
}

}  // namespace
}  // namespace carril::fw
