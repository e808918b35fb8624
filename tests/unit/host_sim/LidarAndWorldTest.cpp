// Lidar ray casts return known distances; the world moves the robot through its wheels;
// contacts are counted once per start.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "hal/Types.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/unit/host_sim/SimTestScenario.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

Scenario box_scenario(const char* preset, const char* extra = "") {
  std::string yaml = std::string(R"(
name: lidar_box
duration_s: 1
robot: {preset: )") + preset +
                     R"(}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-20, -20], [-19, -20]]}]
obstacles: [{shape: box, x: 3.0, y: 0.0, size_m: [1.0, 1.0]}]
)" + extra;
  return test::load_text(yaml);
}

TEST(LidarSimTest, CentreBeamMeasuresDistanceToBoxFace) {
  // pioneer3at lidar: at x = 0.20 on the centre line, facing forward, 180 deg, 361 beams.
  // Box face at x = 3.0 - 0.5 = 2.5 -> range 2.3 m on the beam at 0 deg (index 180).
  Scenario s = box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  auto scan = std::make_unique<hal::LaserScan>();
  lidar.scan(world, *scan);
  ASSERT_EQ(scan->count, 361);
  EXPECT_NEAR(scan->angle_min_rad, -90 * kDeg, 1e-6);
  EXPECT_NEAR(scan->angle_increment_rad, 0.5 * kDeg, 1e-6);
  EXPECT_NEAR(scan->ranges_m[180], 2.3, 1e-3);
  // 10 deg off-axis the ray still hits the face: 2.3 / cos(10 deg).
  EXPECT_NEAR(scan->ranges_m[200], 2.3 / std::cos(10 * kDeg), 1e-3);
  // Straight left there is nothing: no return is +inf.
  EXPECT_TRUE(std::isinf(scan->ranges_m[360]));
}

TEST(LidarSimTest, OffCentreRotatedMountSeesTheSameBox) {
  // campero lidar: mount (0.45, -0.35), heading -45 deg, 270 deg fov, 541 beams (0.5 deg).
  // The beam pointing along robot +x is at -(-45) = +45 deg in the sensor frame:
  // index (45 + 135) / 0.5 = 360. The box face is 2.5 - 0.45 = 2.05 m ahead of the mount.
  Scenario s = box_scenario("campero");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  auto scan = std::make_unique<hal::LaserScan>();
  lidar.scan(world, *scan);
  ASSERT_EQ(scan->count, 541);
  EXPECT_NEAR(scan->ranges_m[360], 2.05, 1e-3);
}

TEST(LidarSimTest, NoiseHasTheConfiguredSpread) {
  Scenario s = box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.02;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 3);
  auto scan = std::make_unique<hal::LaserScan>();
  double sum = 0, sum2 = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    lidar.scan(world, *scan);
    const double e = scan->ranges_m[180] - 2.3;
    sum += e;
    sum2 += e * e;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.005);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.004);
}

TEST(SimWorldTest, MecanumRobotMovesSideways) {
  Scenario s = box_scenario("campero");
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
  Scenario s = box_scenario("pioneer3at");
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
  Scenario s = box_scenario("pioneer3at");
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

}  // namespace
}  // namespace carril::sim
