// Lidar ray casts return known distances, from centred and off-centre rotated mounts, with the
// configured noise.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hal/Types.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(LidarSimTest, CentreBeamMeasuresDistanceToBoxFace) {
  // pioneer3at lidar: at x = 0.20 on the centre line, facing forward, 180 deg, 361 beams.
  // Box face at x = 3.0 - 0.5 = 2.5 -> range 2.3 m on the beam at 0 deg (index 180).
  Scenario s = test::box_scenario("pioneer3at");
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
  Scenario s = test::box_scenario("campero");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  auto scan = std::make_unique<hal::LaserScan>();
  lidar.scan(world, *scan);
  ASSERT_EQ(scan->count, 541);
  EXPECT_NEAR(scan->ranges_m[360], 2.05, 1e-3);
}

TEST(LidarSimTest, NoiseHasTheConfiguredSpread) {
  Scenario s = test::box_scenario("pioneer3at");
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

TEST(LidarSimTest, DroppedBeamsReportNoReturnAtTheRateAsked) {
  Scenario s = test::box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  auto scan = std::make_unique<hal::LaserScan>();
  LidarSim clean(s.robot.lidar, 1);
  clean.scan(world, *scan);
  const float before = scan->ranges_m[180];
  ASSERT_FALSE(std::isinf(before));
  s.robot.lidar.dropout = 0.3;
  LidarSim lossy(s.robot.lidar, 1);
  // Beam 180 sees the box: over 200 scans it is lost about 30 % of the time, else unchanged.
  int lost = 0;
  for (int k = 0; k < 200; ++k) {
    lossy.scan(world, *scan);
    if (std::isinf(scan->ranges_m[180])) {
      ++lost;
    } else {
      EXPECT_FLOAT_EQ(scan->ranges_m[180], before);
    }
  }
  EXPECT_NEAR(lost / 200.0, 0.3, 0.1);
}

}  // namespace
}  // namespace carril::sim
