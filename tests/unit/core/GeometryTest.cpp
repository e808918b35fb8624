#include "firmware/core/Geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::fw {
namespace {

TEST(GeometryTest, PoseFrameMovesPointsLikeTheOnePointFunctionsBitForBit) {
  // The loops that moved to PoseFrame must see exactly the values they saw before.
  for (int k = 0; k < 50; ++k) {
    const Pose2 pose{0.37 * k - 4.0, 1.0 - 0.11 * k, -3.1 + 0.127 * k};
    const PoseFrame frame(pose);
    const Vec2 q(0.3 * std::sin(k), 2.0 - 0.05 * k);
    const Vec2 w = frame.to_world(q);
    const Vec2 r = frame.to_robot(q);
    // The reference formulas, spelled out.
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    EXPECT_EQ(w.x(), pose.x + c * q.x() - s * q.y());
    EXPECT_EQ(w.y(), pose.y + s * q.x() + c * q.y());
    const double dx = q.x() - pose.x, dy = q.y() - pose.y;
    EXPECT_EQ(r.x(), c * dx + s * dy);
    EXPECT_EQ(r.y(), -s * dx + c * dy);
    EXPECT_EQ(to_world(pose, q), w);
    EXPECT_EQ(to_robot(pose, q), r);
    // And they are each other's inverse.
    const Vec2 back = frame.to_robot(w);
    EXPECT_NEAR(back.x(), q.x(), 1e-12);
    EXPECT_NEAR(back.y(), q.y(), 1e-12);
  }
}

TEST(GeometryTest, PoseFrameTurnsAQuarterTurnTheRightWay) {
  const PoseFrame frame(Pose2{1.0, 2.0, kPi / 2});
  const Vec2 w = frame.to_world(Vec2(1.0, 0.0));  // 1 m ahead of a robot facing +y
  EXPECT_NEAR(w.x(), 1.0, 1e-12);
  EXPECT_NEAR(w.y(), 3.0, 1e-12);
}

}  // namespace
TEST(GeometryTest, FastAtan2IsWithinItsBoundOfLibmAllRound) {
  double worst = 0.0;
  for (int i = 0; i < 3600; ++i) {
    const double a = -kPi + (i + 0.5) * (2.0 * kPi / 3600.0);
    for (const double r : {1e-3, 0.7, 25.0}) {
      const double x = r * std::cos(a), y = r * std::sin(a);
      worst = std::fmax(worst, std::fabs(fast_atan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(worst, 2e-5);
  EXPECT_GT(worst, 0.0);  // an approximation: equal to libm would mean the test compares nothing
  // The axes and the origin exactly.
  EXPECT_EQ(fast_atan2(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(fast_atan2(1.0, 0.0), 0.5 * kPi);
  EXPECT_DOUBLE_EQ(fast_atan2(-1.0, 0.0), -0.5 * kPi);
  EXPECT_DOUBLE_EQ(fast_atan2(0.0, -1.0), kPi);
  EXPECT_EQ(fast_atan2(0.0, 0.0), 0.0);
}

}  // namespace carril::fw
