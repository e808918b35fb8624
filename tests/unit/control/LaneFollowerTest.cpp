// The lane follower on a coverage route: a lane, a U-turn of half the lane spacing, the next
// lane back; tracking, the speed cut on the arc, the end, no allocation.
#include "firmware/control/LaneFollower.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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

// A robot whose yaw rate follows the command at most 3 rad/s^2 (the firmware's motion limiter)
// and whose speed at most 0.9 m/s^2.
struct Lagging {
  Pose2 pose;
  Twist now;
  void step(const Twist& cmd, double dt) {
    now.vx += clampd(cmd.vx - now.vx, -0.9 * dt, 0.9 * dt);
    now.wz += clampd(cmd.wz - now.wz, -3.0 * dt, 3.0 * dt);
    integrate(pose, now, dt);
  }
};

// Up x = 0 to y = 1, a half circle of radius r over the top (a point every 0.3 rad, as the
// decomposition lays them), down x = 2r to y = 0.
std::vector<Vec2> u_turn_route(double r) {
  std::vector<Vec2> p = {{0.0, 0.0}, {0.0, 1.0}};
  const int steps = int(std::ceil(kPi / 0.3));
  for (int s = 1; s < steps; ++s) {
    const double a = kPi - kPi * s / steps;
    p.push_back({r + r * std::cos(a), 1.0 + r * std::sin(a)});
  }
  p.push_back({2.0 * r, 1.0});
  p.push_back({2.0 * r, 0.0});
  return p;
}

// Distance from q to the route's ideal shape [m].
double off_route(const Vec2& q, double r) {
  if (q.y() <= 1.0) return std::fmin(std::fabs(q.x()), std::fabs(q.x() - 2.0 * r));
  return std::fabs((q - Vec2(r, 1.0)).norm() - r);
}

TEST(LaneFollowerTest, ConfigValidateNamesTheKey) {
  LaneFollowerConfig cfg;
  EXPECT_TRUE(cfg.validate().is_ok());
  cfg.cross_track_gain = -1.0;
  EXPECT_NE(std::string(cfg.validate().message()).find("lane_follower.cross_track_gain"),
            std::string::npos);
}

TEST(LaneFollowerTest, CurvatureOfAnArcPolylineIsItsRadius) {
  const double r = 0.15;
  const std::vector<Vec2> p = u_turn_route(r);
  // On the arc (its first point past the lane): left-handed route, so a right turn (negative).
  const PathProjection at = project_on_path(p.data(), p.size(), Vec2(0.0, 1.0), 0, 4);
  const double k = path_curvature(p.data(), p.size(), at, 0.03, 0.11);
  EXPECT_NEAR(k, -1.0 / r, 0.1 / r);
  // On the lane, well before the arc: straight.
  const PathProjection low = project_on_path(p.data(), p.size(), Vec2(0.0, 0.3), 0, 4);
  EXPECT_NEAR(path_curvature(p.data(), p.size(), low, 0.03, 0.11), 0.0, 1e-9);
  EXPECT_NEAR(path_heading(p.data(), p.size(), low), kPi / 2, 1e-9);
}

TEST(LaneFollowerTest, FollowsAUTurnOfHalfTheLaneSpacingClosely) {
  const double r = 0.154;  // a 0.308 m lane spacing
  const std::vector<Vec2> p = u_turn_route(r);
  LaneFollowerConfig cfg;
  cfg.cruise_speed_mps = 0.3;
  cfg.max_yaw_rate_radps = 1.9;
  LaneFollower f(cfg);
  Lagging robot{{0.0, 0.0, kPi / 2}, {}};
  const Pose2& pose = robot.pose;
  double worst = 0.0, top = 0.0, slowest_on_arc = 1.0, fastest = 0.0;
  int steps = 0;
  const auto before = alloc::count_total();
  for (; steps < 3000 && !f.at_end(); ++steps) {
    const Twist t = f.update(pose, p.data(), p.size());
    EXPECT_LE(std::fabs(t.wz), cfg.max_yaw_rate_radps + 1e-9);
    fastest = std::fmax(fastest, t.vx);
    if (pose.y > 1.0) slowest_on_arc = std::fmin(slowest_on_arc, t.vx);
    robot.step(t, 0.01);
    worst = std::fmax(worst, off_route(Vec2(pose.x, pose.y), r));
    top = std::fmax(top, pose.y);
  }
  EXPECT_EQ(alloc::count_total(), before);
  EXPECT_TRUE(f.at_end());
  // Within 2.5 cm of the route all the way (the yaw rate lags the arc's start), and the U-turn
  // reaches its top (the lane end cells).
  EXPECT_LT(worst, 0.025);
  EXPECT_GT(top, 1.0 + r - 0.02);
  EXPECT_NEAR(fastest, 0.3, 1e-9);
  // The arc needs 0.3 / 0.154 = 1.95 rad/s at cruise: driven slower, not stopped.
  EXPECT_LT(slowest_on_arc, 0.3);
  EXPECT_GT(slowest_on_arc, 0.2);
}

TEST(LaneFollowerTest, ConvergesOntoALaneFromAnOffsetAndTurnsOnTheSpotWhenFacingAway) {
  const std::vector<Vec2> p = {{0.0, 0.0}, {4.0, 0.0}};
  LaneFollower f;
  Pose2 pose{0.0, 0.1, 0.0};
  for (int i = 0; i < 400; ++i) integrate(pose, f.update(pose, p.data(), p.size()), 0.01);
  EXPECT_LT(std::fabs(pose.y), 0.01);
  f.update(pose, p.data(), p.size());
  EXPECT_NEAR(f.cross_track_m(), -pose.y, 1e-9);
  f.reset();
  const Pose2 away{0.0, 0.0, kPi};
  const Twist t = f.update(away, p.data(), p.size());
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_NE(t.wz, 0.0);
}

// Turning onto a lane at right angles, a robot whose yaw rate lags at 3 rad/s^2: with the braking
// it stops turning close to the lane's heading; without it, the heading gain of 4 asks for more
// deceleration than the robot has near the heading, and it swings well past (in the simulator,
// where the wheels' acceleration is shared with the start of the drive, on into a door's jamb).
TEST(LaneFollowerTest, TurningOntoALaneItBrakesForTheYawAccelerationAndDoesNotSwingPast) {
  const std::vector<Vec2> p = {{0.0, 0.0}, {0.0, 3.0}};
  const auto run = [&](double accel, double& overshoot) {
    LaneFollowerConfig cfg;
    cfg.max_yaw_rate_radps = 1.9;
    cfg.max_yaw_accel_radps2 = accel;
    LaneFollower f(cfg);
    Lagging robot;
    robot.pose = Pose2{0.0, 0.0, 0.0};
    overshoot = 0.0;
    for (int i = 0; i < 400; ++i) {
      robot.step(f.update(robot.pose, p.data(), p.size()), 0.01);
      overshoot = std::fmax(overshoot, robot.pose.yaw - 0.5 * kPi);
    }
    EXPECT_GT(robot.pose.y, 0.5);  // it got going
  };
  double braked = 0.0, plain = 0.0;
  run(3.0, braked);
  run(0.0, plain);
  std::printf("swung past the lane's heading by %.3f rad (without the braking %.3f rad)\n", braked,
              plain);
  EXPECT_LT(braked, 0.07);
  EXPECT_GT(plain, 0.1);  // the case the braking is for
  EXPECT_LT(braked, 0.5 * plain);
}

// Past the end of a short segment onto a lane at right angles (where a cell's sweep starts beside
// its lane), the corner's vertex is the nearest point of both segments: the follower takes the
// lane, not the short segment's heading on past the corner.
TEST(LaneFollowerTest, PastACornersVertexItTakesTheNextSegment) {
  const std::vector<Vec2> p = {{0.0, 0.0}, {0.08, 0.0}, {0.08, -2.0}};
  LaneFollower f;
  const Pose2 past{0.11, 0.0, 0.0};
  const Twist t = f.update(past, p.data(), p.size());
  EXPECT_EQ(f.progress(), 1u);
  EXPECT_EQ(t.vx, 0.0);  // turns on the spot toward the lane
  EXPECT_LT(t.wz, 0.0);
  // Driven through from the first point: down the lane, never far past the corner.
  LaneFollower g;
  Lagging robot;
  double east = 0.0;
  for (int i = 0; i < 1500 && !g.at_end(); ++i) {
    robot.step(g.update(robot.pose, p.data(), p.size()), 0.01);
    east = std::fmax(east, robot.pose.x);
  }
  EXPECT_TRUE(g.at_end());
  EXPECT_LT(east, 0.15);
}

// A robot that reaches the end wider than goal_tolerance (8 cm to the side) stops there: driving
// on, it would follow the lane's line past its end, faster as the end fell behind.
TEST(LaneFollowerTest, StopsOnceItIsPastTheEndHoweverWideOfIt) {
  const std::vector<Vec2> p = {{0.0, 0.0}, {1.0, 0.0}};
  LaneFollowerConfig cfg;
  cfg.cross_track_gain = 0.0;  // nothing pulls it onto the line before the end
  cfg.heading_gain = 0.0;
  LaneFollower f(cfg);
  Pose2 pose{0.8, 0.08, 0.0};
  const Twist before = f.update(pose, p.data(), p.size());
  EXPECT_GT(before.vx, 0.0);
  EXPECT_FALSE(f.at_end());
  for (int i = 0; i < 300 && !f.at_end(); ++i) {
    integrate(pose, f.update(pose, p.data(), p.size()), 0.01);
  }
  EXPECT_TRUE(f.at_end());
  EXPECT_GE(pose.x, 1.0);
  EXPECT_LT(pose.x, 1.01);  // one step past the end's line at most
  const Twist after = f.update(pose, p.data(), p.size());
  EXPECT_EQ(after.vx, 0.0);
  EXPECT_EQ(after.wz, 0.0);
  // Just before the end's line it still drives.
  f.reset();
  const Twist near = f.update(Pose2{0.99, 0.08, 0.0}, p.data(), p.size());
  EXPECT_GT(near.vx, 0.0);
  EXPECT_FALSE(f.at_end());
}

}  // namespace
}  // namespace carril::fw
