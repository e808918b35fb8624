// PathTracker: the motion primitives the missions share (turn to a heading, drive to a point,
// follow waypoints, creep onto a goal).
#include "firmware/control/PathTracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace carril::fw {
namespace {

constexpr double kDt = 0.01;  // [s]

PathTracker tracker(bool holonomic) {
  return PathTracker(PathTrackerConfig{}, holonomic);
}

// Integrates a body twist over dt (robot frame to odometry frame).
void integrate_pose(Pose2& p, const Twist& t, double dt) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  p.x += (c * t.vx - s * t.vy) * dt;
  p.y += (s * t.vx + c * t.vy) * dt;
  p.yaw = wrap_angle(p.yaw + t.wz * dt);
}

TEST(PathTrackerDriveTo, HolonomicTranslatesTowardTheWaypointAndHoldsHeading) {
  bool reached = true;
  const Pose2 o{0.0, 0.0, 0.3};
  const Vec2 wp(1.0, 1.0);
  const Twist t = tracker(true).drive_to(o, wp, 0.0, 0.3, reached);
  EXPECT_FALSE(reached);
  const Vec2 e = to_robot(o, wp);
  EXPECT_NEAR(std::atan2(t.vy, t.vx), std::atan2(e.y(), e.x()), 1e-9);
  EXPECT_NEAR(std::hypot(t.vx, t.vy), 0.3 + 0.03, 1e-9);
  EXPECT_NEAR(t.wz, -0.6, 1e-9);  // back toward the held heading
  const Twist u = tracker(true).drive_to(Pose2{0.0, 0.0, 0.0}, wp, 0.0, 0.3, reached);
  EXPECT_EQ(u.wz, 0.0);
}

TEST(PathTrackerDriveTo, DifferentialTurnsOnTheSpotWhenTheBearingIsLarge) {
  bool reached = true;
  const Twist l = tracker(false).drive_to(Pose2{}, Vec2(0.0, 1.0), 0.0, 0.3, reached);
  EXPECT_FALSE(reached);
  EXPECT_EQ(l.vx, 0.0);
  EXPECT_EQ(l.vy, 0.0);
  EXPECT_GT(l.wz, 0.0);
  const Twist r = tracker(false).drive_to(Pose2{}, Vec2(0.2, -1.0), 0.0, 0.3, reached);
  EXPECT_EQ(r.vx, 0.0);
  EXPECT_LT(r.wz, 0.0);
  const Twist b = tracker(false).drive_to(Pose2{}, Vec2(-1.0, 0.01), 0.0, 0.3, reached);  // behind
  EXPECT_EQ(b.vx, 0.0);
  EXPECT_NE(b.wz, 0.0);
}

TEST(PathTrackerDriveTo, DifferentialDrivesWhenTheBearingIsSmall) {
  bool reached = true;
  const Twist t = tracker(false).drive_to(Pose2{}, Vec2(1.0, 0.05), 0.0, 0.3, reached);
  EXPECT_FALSE(reached);
  EXPECT_GT(t.vx, 0.0);
  EXPECT_EQ(t.vy, 0.0);
  EXPECT_GT(t.wz, 0.0);
  EXPECT_NEAR(t.wz, 2.0 * std::atan2(0.05, 1.0), 1e-9);
}

TEST(PathTrackerDriveTo, ReachedWithinFourCentimetres) {
  for (const bool holo : {true, false}) {
    bool reached = false;
    const Twist in = tracker(holo).drive_to(Pose2{}, Vec2(0.039, 0.0), 0.0, 0.3, reached);
    EXPECT_TRUE(reached);
    EXPECT_EQ(in.vx, 0.0);
    EXPECT_EQ(in.vy, 0.0);
    EXPECT_EQ(in.wz, 0.0);
    const Twist out = tracker(holo).drive_to(Pose2{}, Vec2(0.041, 0.0), 0.0, 0.3, reached);
    EXPECT_FALSE(reached);
    EXPECT_GT(out.vx, 0.0);
  }
}

TEST(PathTrackerDriveTo, ClosedLoopReachesTheWaypoint) {
  for (const bool holo : {true, false}) {
    for (const Vec2 wp : {Vec2(1.0, 0.0), Vec2(0.0, 1.05), Vec2(-0.5, -0.8), Vec2(0.15, -1.05)}) {
      Pose2 p{0.0, 0.0, 0.0};
      bool reached = false;
      int ticks = 0;
      for (; ticks < 3000 && !reached; ++ticks) {
        const Twist t = tracker(holo).drive_to(p, wp, 0.0, 0.3, reached);
        integrate_pose(p, t, kDt);
        if (holo) ASSERT_LT(std::fabs(p.yaw), 1e-9);
      }
      EXPECT_TRUE(reached) << "holo=" << holo << " wp=" << wp.transpose();
      EXPECT_LT((Vec2(p.x, p.y) - wp).norm(), 0.04);
    }
  }
}

TEST(PathTrackerTurnTo, TurnsTheShortWayAndSaturates) {
  const PathTracker pt(PathTrackerConfig{2.0, 0.6, 0.04}, false);
  EXPECT_NEAR(pt.turn_to(Pose2{0, 0, 0.0}, 0.1).wz, 0.2, 1e-12);
  EXPECT_NEAR(pt.turn_to(Pose2{0, 0, 0.0}, -0.1).wz, -0.2, 1e-12);
  EXPECT_EQ(pt.turn_to(Pose2{0, 0, 0.0}, 2.0).wz, 0.6);
  // 3.0 rad to -3.0 rad is 0.28 rad to the left, not 6 rad to the right.
  EXPECT_GT(pt.turn_to(Pose2{0, 0, 3.0}, -3.0).wz, 0.0);
  const Twist t = pt.turn_to(Pose2{0, 0, 0.0}, 1.0);
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_EQ(t.vy, 0.0);
}

TEST(PathTrackerFollow, VisitsEveryWaypointInOrderThenIsDone) {
  for (const bool holo : {true, false}) {
    const PathTracker pt = tracker(holo);
    const Vec2 wps[] = {Vec2(0.5, 0.0), Vec2(0.5, 0.5), Vec2(1.0, 0.5)};
    Pose2 p{};
    std::size_t i = 0;
    bool done = false;
    std::size_t last_i = 0;
    for (int tick = 0; tick < 6000 && !done; ++tick) {
      const Twist t = pt.follow(p, wps, 3, i, 0.0, 0.3, done);
      ASSERT_GE(i, last_i);  // never goes back
      if (i > last_i) {
        EXPECT_LT((Vec2(p.x, p.y) - wps[last_i]).norm(), 0.04 + 1e-9) << "skipped " << last_i;
        last_i = i;
      }
      integrate_pose(p, t, kDt);
    }
    EXPECT_TRUE(done) << "holo=" << holo;
    EXPECT_EQ(i, 3U);
    bool again = false;
    const Twist z = pt.follow(p, wps, 3, i, 0.0, 0.3, again);
    EXPECT_TRUE(again);
    EXPECT_EQ(z.vx, 0.0);
    EXPECT_EQ(z.wz, 0.0);
  }
}

TEST(PathTrackerApproach, CreepsOntoTheGoalAndStopsWithinTolerance) {
  for (const bool holo : {true, false}) {
    const PathTracker pt = tracker(holo);
    Pose2 p{0.0, 0.0, 0.0};
    const Vec2 goal(0.6, holo ? 0.2 : 0.02);
    bool arrived = false;
    double max_speed = 0.0;
    for (int tick = 0; tick < 5000 && !arrived; ++tick) {
      const Twist t = pt.approach(p, goal, 0.25, 1.5, 0.005, arrived);
      max_speed = std::fmax(max_speed, std::hypot(t.vx, t.vy));
      integrate_pose(p, t, kDt);
    }
    EXPECT_TRUE(arrived) << "holo=" << holo;
    EXPECT_LE(max_speed, 0.25 + 1e-12);
    EXPECT_LT((Vec2(p.x, p.y) - goal).norm(), holo ? 0.005 : 0.05);
  }
}

TEST(PathTrackerConfigTest, ValidateNamesTheField) {
  EXPECT_TRUE(PathTrackerConfig{}.validate().is_ok());
  PathTrackerConfig c;
  c.max_turn_rate_radps = 0.0;
  const Status s = c.validate();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("path.max_turn_rate_radps"), std::string::npos)
      << s.message();
  EXPECT_NE(std::string(s.message()).find("rad/s"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace carril::fw
