// The world moves the robot through its wheels; contacts are counted once per start.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "hal/Types.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

TEST(SimWorldTest, MecanumRobotMovesSideways) {
  Scenario s = test::box_scenario("campero");
  s.obstacles.clear();
  SimWorld world(s);
  fw::DriveKinematics kin(drive_geometry(s.robot));
  float w[4];
  kin.inverse({0.0, 0.5, 0.0}, w);  // 0.5 m/s to the left
  world.set_wheel_targets(w);
  for (int i = 0; i < 400; ++i) world.step(0.005);  // 2 s
  const Pose2 p = world.pose();
  // Wheels ramp at 25 rad/s^2 to 3.94 rad/s (0.16 s), so about 0.04 m is lost to the ramp.
  EXPECT_NEAR(p.y, 1.0 - 0.04, 0.01);
  EXPECT_NEAR(p.x, 0.0, 1e-3);
  EXPECT_NEAR(p.yaw_rad, 0.0, 1e-3);
  double vx = 0, vy = 0, wz = 0;
  world.body_velocity(vx, vy, wz);
  EXPECT_NEAR(vy, 0.5, 1e-3);
}

TEST(SimWorldTest, DifferentialRobotCannotMoveSideways) {
  Scenario s = test::box_scenario("pioneer3at");
  s.obstacles.clear();
  SimWorld world(s);
  fw::DriveKinematics kin(drive_geometry(s.robot));
  float w[2];
  kin.inverse({0.0, 0.5, 0.0}, w);
  world.set_wheel_targets(w);
  for (int i = 0; i < 200; ++i) world.step(0.005);
  EXPECT_NEAR(world.pose().y, 0.0, 1e-6);
}

TEST(SimWorldTest, DrivingIntoABoxCountsOneCollisionAndStops) {
  Scenario s = test::box_scenario("pioneer3at");
  SimWorld world(s);
  fw::DriveKinematics kin(drive_geometry(s.robot));
  float w[2];
  kin.inverse({0.5, 0.0, 0.0}, w);
  world.set_wheel_targets(w);
  for (int i = 0; i < 2000; ++i) world.step(0.005);  // 10 s: would be 5 m unobstructed
  EXPECT_EQ(world.collisions(), 1);
  // Front of the body (0.254 m ahead of centre) is stopped at the box face x = 2.5.
  EXPECT_NEAR(world.pose().x, 2.5 - 0.254, 0.03);
  EXPECT_EQ(world.take_new_contacts().size(), 1U);
  EXPECT_TRUE(world.take_new_contacts().empty());
}

// Issue 46 item 2: a mover walks its path at its speed from its start time; one that walks into
// a robot standing still is its contact, not the robot's collision; a robot that drives into a
// mover standing in its way collides as with any obstacle.
TEST(SimWorldTest, AMoverWalksItsPathAndItsContactsAreToldApart) {
  // The box at x 3 is moved out of the way; a person starts 2 m beside the robot at t = 1 s.
  Scenario s = test::box_scenario(
      "pioneer3at",
      "movers: [{shape: cylinder, radius_m: 0.25, path: [[0, -2], [0, 2]], speed_mps: 1.6, "
      "start_s: 1.0}]\n");
  s.obstacles.clear();
  SimWorld world(s);
  for (int i = 0; i < 200; ++i) world.step(0.005);  // t = 1 s: still at its first point
  EXPECT_NEAR(world.mover_position(0).y, -2.0, 1e-3);
  for (int i = 0; i < 100; ++i) world.step(0.005);  // 0.5 s walking: 0.8 m
  EXPECT_NEAR(world.mover_position(0).y, -1.2, 0.01);
  for (int i = 0; i < 600; ++i) world.step(0.005);  // it walks through where the robot stands
  EXPECT_EQ(world.mover_contacts(), 1);
  EXPECT_EQ(world.collisions(), 0);
  EXPECT_GT(std::fabs(world.pose().y) + std::fabs(world.pose().x), 0.05);  // pushed aside

  // The same person standing on the robot's way (it sets off after the run): driven into.
  Scenario d = test::box_scenario(
      "pioneer3at",
      "movers: [{shape: cylinder, radius_m: 0.25, path: [[1.5, 0], [1.5, 2]], speed_mps: 1.0, "
      "start_s: 100}]\n");
  d.obstacles.clear();
  SimWorld drive(d);
  fw::DriveKinematics kin(drive_geometry(d.robot));
  float w[2];
  kin.inverse({0.5, 0.0, 0.0}, w);
  drive.set_wheel_targets(w);
  for (int i = 0; i < 1000; ++i) drive.step(0.005);
  EXPECT_EQ(drive.collisions(), 1);
  EXPECT_EQ(drive.mover_contacts(), 0);
}

// SimWorld.cpp defines b2Timer so that Box2D's step profile never reads the clock; libbox2d must
// call that definition, not its own (which would read gettimeofday a dozen times a step).
TEST(SimWorldTest, Box2DsStepTimerIsTheSimulatorsOwn) {
  b2World world(b2Vec2(0.0F, -10.0F));
  b2BodyDef ground_def;
  b2PolygonShape ground;
  ground.SetAsBox(50.0F, 1.0F);
  world.CreateBody(&ground_def)->CreateFixture(&ground, 0.0F);
  b2PolygonShape box;
  box.SetAsBox(0.5F, 0.5F);
  for (int i = 0; i < 200; ++i) {  // a pile of boxes: each step takes tens of microseconds
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position.Set(float(i % 20) * 1.01F - 10.0F, 2.0F + float(i / 20) * 1.01F);
    world.CreateBody(&bd)->CreateFixture(&box, 1.0F);
  }
  float total_ms = 0.0F;
  for (int i = 0; i < 100; ++i) {
    world.Step(1.0F / 60.0F, 8, 3);
    const b2Profile& p = world.GetProfile();
    total_ms += p.step + p.collide + p.solve + p.solveInit + p.solveVelocity + p.solvePosition +
                p.broadphase + p.solveTOI;
  }
  EXPECT_EQ(total_ms, 0.0F);
  const b2Timer t;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2);
  while (std::chrono::steady_clock::now() < until) {
  }
  EXPECT_EQ(t.GetMilliseconds(), 0.0F);
}

}  // namespace
}  // namespace carril::sim
