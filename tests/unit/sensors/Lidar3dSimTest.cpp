// The simulated 3D lidar against small analytic surfaces: ranges on a flat floor, the blind zone,
// occlusion behind a cube and beyond a step down, the sky, noise and beam drops per seed, a
// pitched body, the config checks, the robot presets' `lidar3d:` blocks and the HAL sensor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <string>

#include "hal/sim/SimPointCloud.hpp"
#include "host_sim/sensors/Lidar3dSim.hpp"
#include "loader/RobotLoader.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kH = 0.5;  // sensor height above the floor [m]

// z = 0 everywhere.
class FlatFloor : public HeightQuery {
 public:
  double height_at(double, double) const override { return 0.0; }
  double max_height() const override { return 0.0; }
  double min_height() const override { return 0.0; }
};

// A 1 m cube standing on the floor, its near face at x = 3, y in [-0.5, 0.5].
class Cube : public HeightQuery {
 public:
  double height_at(double x, double y) const override {
    return (x >= 3.0 && x <= 4.0 && std::fabs(y) <= 0.5) ? 1.0 : 0.0;
  }
  double max_height() const override { return 1.0; }
  double min_height() const override { return 0.0; }
};

// The floor drops by 0.2 m at x = 2.
class StepDown : public HeightQuery {
 public:
  double height_at(double x, double) const override { return x < 2.0 ? 0.0 : -0.2; }
  double max_height() const override { return 0.0; }
  double min_height() const override { return -0.2; }
};

// An endless ramp rising along +x at `deg`, through z = 0 at x = 0.
class Ramp : public HeightQuery {
 public:
  explicit Ramp(double deg) : slope_(std::tan(deg * kDeg)) {}
  double height_at(double x, double) const override { return slope_ * x; }
  double max_height() const override { return 1e3; }
  double min_height() const override { return -1e3; }

 private:
  double slope_;
};

// Garbage from the world: NaN heights everywhere.
class NanWorld : public HeightQuery {
 public:
  double height_at(double, double) const override {
    return std::numeric_limits<double>::quiet_NaN();
  }
  double max_height() const override { return 1.0; }
  double min_height() const override { return -1.0; }
};

// The HDL-32E at kH above the floor, no noise, 1 m blind zone, 20 m range.
Lidar3dConfig hdl32() {
  Lidar3dConfig c;
  c.sensor.present = true;
  c.sensor.z_m = kH;
  return c;
}

double range_of(const hal::CloudPoint& p) {
  return std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
}

struct Sweep {
  std::unique_ptr<hal::PointCloud> cloud = std::make_unique<hal::PointCloud>();
};

Sweep render(const Lidar3dConfig& c, const HeightQuery& w, const BodyPose3& pose = {},
             std::uint64_t seed = 1) {
  EXPECT_TRUE(c.validate().is_ok()) << c.validate().message();
  Lidar3dSim sim(c, seed);
  Sweep r;
  sim.render(w, pose, 123, *r.cloud);
  return r;
}

// Rings whose beam meets a flat floor kH below within [range_min, range_max].
int rings_on_floor(const Lidar3dConfig& c, const Lidar3dSim& sim) {
  int n = 0;
  for (int r = 0; r < c.sensor.rings; ++r) {
    const double e = sim.ring_elevation_rad(r);
    if (e >= 0) continue;
    const double range = kH / std::sin(-e);
    if (range >= c.sensor.range_min_m && range <= c.sensor.range_max_m) ++n;
  }
  return n;
}

TEST(Lidar3dSimTest, FlatFloorRingsHitAtHeightOverSineOfTheirAngle) {
  Lidar3dConfig c = hdl32();
  c.sensor.range_min_m = 0.0;
  FlatFloor floor;
  Lidar3dSim sim(c, 1);
  auto cloud = std::make_unique<hal::PointCloud>();
  sim.render(floor, {}, 5'000'000, *cloud);
  EXPECT_EQ(cloud->seq, 1U);
  EXPECT_EQ(cloud->stamp_ns, 5'000'000);
  // Every azimuth of every ring that reaches the floor within 20 m: 22 rings (-30.67 .. -2.67).
  ASSERT_EQ(rings_on_floor(c, sim), 22);
  ASSERT_EQ(cloud->count, 22U * 1800U);
  for (std::uint32_t i = 0; i < cloud->count; ++i) {
    const hal::CloudPoint& p = cloud->points[i];
    const double r = range_of(p);
    const double elev = std::asin(double(p.z) / r);
    ASSERT_NEAR(p.z, -kH, 0.01) << i;
    ASSERT_NEAR(r, kH / std::sin(-elev), 0.01) << i;
  }
  // The lowest ring (-30.67 deg) at azimuth 0 is the first point: range 0.5 / sin(30.67 deg).
  EXPECT_NEAR(range_of(cloud->points[0]), kH / std::sin(30.67 * kDeg), 0.01);
  EXPECT_NEAR(cloud->points[0].y, 0.0, 1e-4);
  sim.render(floor, {}, 6'000'000, *cloud);
  EXPECT_EQ(cloud->seq, 2U);
}

TEST(Lidar3dSimTest, BlindZoneDropsReturnsNearerThanRangeMin) {
  // At 0.5 m the lowest ring meets the floor at 0.98 m: inside the HDL-32E's 1 m blind zone.
  Lidar3dConfig c = hdl32();
  FlatFloor floor;
  Sweep with_zone = render(c, floor);
  c.sensor.range_min_m = 0.0;
  Sweep without = render(c, floor);
  EXPECT_EQ(without.cloud->count - with_zone.cloud->count, 1800U);  // one ring fewer
  for (std::uint32_t i = 0; i < with_zone.cloud->count; ++i)
    ASSERT_GE(range_of(with_zone.cloud->points[i]), 1.0) << i;
}

TEST(Lidar3dSimTest, CubeFaceReturnsAndOccludesTheFloorBehindIt) {
  Cube cube;
  Sweep run = render(hdl32(), cube);
  int on_face = 0;
  for (std::uint32_t i = 0; i < run.cloud->count; ++i) {
    const hal::CloudPoint& p = run.cloud->points[i];
    if (std::fabs(p.y) > 0.4 || p.x < 0) continue;  // the wedge the cube covers
    // Nothing beyond the face: not the floor behind it, not the cube's top (above the sensor).
    ASSERT_LT(p.x, 3.01) << "point at x " << p.x << " z " << p.z;
    if (p.x > 2.99) {
      ++on_face;
      EXPECT_GE(p.z, -kH - 0.01);  // on the face: between the floor and the top
      EXPECT_LE(p.z, 1.0 - kH + 0.01);
    }
  }
  // Rings from -9.35 to +9.35 deg (15) cross the face, over the azimuths within |y| <= 0.4.
  EXPECT_GT(on_face, 15 * 20);
}

TEST(Lidar3dSimTest, GroundJustBeyondAStepDownIsNotSeenWhileFarGroundIs) {
  StepDown step;
  Sweep run = render(hdl32(), step);
  int far_lower = 0, near_upper = 0;
  for (std::uint32_t i = 0; i < run.cloud->count; ++i) {
    const hal::CloudPoint& p = run.cloud->points[i];
    if (std::fabs(p.y) > 0.2) continue;
    // A beam grazing the edge at x = 2 from 0.5 m meets the lower floor 0.7 m down at x = 2.8.
    ASSERT_FALSE(p.x > 2.0 && p.x < 2.75) << "point in the shadow at x " << p.x << " z " << p.z;
    if (p.x >= 2.8 && std::fabs(p.z - (-0.2 - kH)) < 0.01) ++far_lower;
    if (p.x < 2.0 && p.x > 1.0 && std::fabs(p.z + kH) < 0.01) ++near_upper;
  }
  EXPECT_GT(far_lower, 10);
  EXPECT_GT(near_upper, 10);
}

TEST(Lidar3dSimTest, BeamsAboveTheHorizonWithNothingThereReturnNothing) {
  Lidar3dConfig c = hdl32();
  c.sensor.vertical_min_deg = 0.0;  // the upper rings only
  c.sensor.vertical_max_deg = 10.67;
  c.sensor.rings = 9;
  FlatFloor floor;
  Cube cube;
  EXPECT_EQ(render(c, floor).cloud->count, 0U);
  // The cube rises above the sensor: only the beams that meet its face return.
  Sweep run = render(c, cube);
  ASSERT_GT(run.cloud->count, 0U);
  for (std::uint32_t i = 0; i < run.cloud->count; ++i)
    ASSERT_NEAR(run.cloud->points[i].x, 3.0, 0.01);
}

TEST(Lidar3dSimTest, NoiseIsDeterministicPerSeedAndHasTheConfiguredSpread) {
  Lidar3dConfig c = hdl32();
  c.sensor.noise_std_m = 0.02;
  FlatFloor floor;
  Sweep a = render(c, floor, {}, 7), b = render(c, floor, {}, 7), other = render(c, floor, {}, 8);
  ASSERT_EQ(a.cloud->count, b.cloud->count);
  int differ = 0;
  double sum2 = 0.0;
  for (std::uint32_t i = 0; i < a.cloud->count; ++i) {
    const hal::CloudPoint &p = a.cloud->points[i], &q = b.cloud->points[i];
    ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << i;
    const hal::CloudPoint& o = other.cloud->points[i];
    if (i < other.cloud->count && (o.x != p.x || o.y != p.y || o.z != p.z)) ++differ;
    const double r = range_of(p), truth = kH / (-double(p.z) / r);
    sum2 += (r - truth) * (r - truth);
  }
  EXPECT_GT(differ, int(a.cloud->count) / 2);
  EXPECT_NEAR(std::sqrt(sum2 / a.cloud->count), 0.02, 0.002);
}

TEST(Lidar3dSimTest, DropProbabilityLosesAboutThatFractionOfBeams) {
  Lidar3dConfig c = hdl32();
  FlatFloor floor;
  const double all = render(c, floor).cloud->count;
  c.sensor.drop_probability = 0.3;
  const double kept = render(c, floor).cloud->count;
  EXPECT_NEAR(kept / all, 0.7, 0.02);
  c.sensor.drop_probability = 1.0;
  EXPECT_EQ(render(c, floor).cloud->count, 0U);
}

// Range of the return at sensor azimuth az_deg and elevation elev_deg, or -1 if there is none
// (not NaN: comparing NaN traps under the tests' floating-point exceptions).
double range_at(const hal::PointCloud& cloud, double az_deg, double elev_deg) {
  for (std::uint32_t i = 0; i < cloud.count; ++i) {
    const hal::CloudPoint& p = cloud.points[i];
    const double r = range_of(p);
    const double az = std::atan2(double(p.y), double(p.x)) / kDeg;
    double daz = std::fabs(az - az_deg);
    if (daz > 180) daz = 360 - daz;
    if (daz < 0.05 && std::fabs(std::asin(double(p.z) / r) / kDeg - elev_deg) < 0.05) return r;
  }
  return -1.0;
}

TEST(Lidar3dSimTest, NoseDownPitchBringsTheFloorAheadNearerAndBehindFarther) {
  FlatFloor floor;
  const Lidar3dConfig c = hdl32();
  const double e = -10.67;  // ring 15
  Sweep level = render(c, floor);
  BodyPose3 pitched;
  pitched.pitch_rad = 5 * kDeg;  // REP 103: nose down
  Sweep down = render(c, floor, pitched);
  // The mount (0, 0, 0.5) tilts with the body: its height becomes 0.5 cos 5 deg.
  const double h = kH * std::cos(5 * kDeg);
  EXPECT_NEAR(range_at(*level.cloud, 0, e), kH / std::sin(-e * kDeg), 0.01);
  EXPECT_NEAR(range_at(*down.cloud, 0, e), h / std::sin((-e + 5) * kDeg), 0.01);
  EXPECT_NEAR(range_at(*down.cloud, 180, e), h / std::sin((-e - 5) * kDeg), 0.01);
}

// Elevation of ring r of the HDL-32E [deg].
double ring_deg(int r) {
  return -30.67 + r * (10.67 + 30.67) / 31.0;
}

TEST(Lidar3dSimTest, OnARampThePatternFollowsTheSlope) {
  // Body on a 5 deg ramp rising ahead (nose up: pitch -5 deg): the sensor sits 0.5 m above the
  // inclined plane along its normal, so every ring meets the ramp as it would a flat floor.
  Ramp ramp(5.0);
  BodyPose3 on_ramp;
  on_ramp.pitch_rad = -5 * kDeg;
  Sweep run = render(hdl32(), ramp, on_ramp);
  for (double az : {0.0, 90.0, 180.0, 270.0}) {
    for (int r : {2, 10, 15}) {
      const double e = ring_deg(r);
      EXPECT_NEAR(range_at(*run.cloud, az, e), kH / std::sin(-e * kDeg), 0.01) << az << " " << r;
    }
  }
}

TEST(Lidar3dSimTest, BodyYawAndMountPlaceTheSensor) {
  // The cube's side face y = -0.5 (x in [3, 4]) seen along the horizontal ring (23, ~0 deg).
  Cube cube;
  const double e = ring_deg(23);
  // Robot at (3.5, -4.5) facing +y, mount 0.5 m forward: sensor at (3.5, -4.0), face 3.5 m ahead.
  Lidar3dConfig c = hdl32();
  c.sensor.x_m = 0.5;
  BodyPose3 pose;
  pose.x_m = 3.5;
  pose.y_m = -4.5;
  pose.yaw_rad = 90 * kDeg;
  Sweep yawed = render(c, cube, pose);
  EXPECT_NEAR(range_at(*yawed.cloud, 0, e), 3.5 / std::cos(e * kDeg), 0.01);
  // Robot facing +x at (3.5, -4.0), sensor turned 90 deg left on its mount: the same view.
  c.sensor.x_m = 0.0;
  c.sensor.yaw_deg = 90.0;
  pose.y_m = -4.0;
  pose.yaw_rad = 0.0;
  Sweep mounted = render(c, cube, pose);
  EXPECT_NEAR(range_at(*mounted.cloud, 0, e), 3.5 / std::cos(e * kDeg), 0.01);
}

TEST(Lidar3dSimTest, NanSurfaceGivesNoPointsAndNoTrap) {
  NanWorld nan;
  EXPECT_EQ(render(hdl32(), nan).cloud->count, 0U);
}

TEST(Lidar3dSimTest, ValidateNamesTheKey) {
  Lidar3dConfig c = hdl32();
  EXPECT_TRUE(c.validate().is_ok()) << c.validate().message();
  c.sensor.rings = 0;
  EXPECT_STREQ(c.validate().message(), "lidar3d.rings: 0 rings, expected 1 to 128 rings");
  c = hdl32();
  c.sensor.azimuths = 4096;  // 32 x 4096 > 65536
  EXPECT_NE(std::string(c.validate().message()).find("lidar3d.azimuths"), std::string::npos);
  c = hdl32();
  c.sensor.range_min_m = 25.0;
  EXPECT_NE(std::string(c.validate().message()).find("lidar3d.range_min_m"), std::string::npos);
  c = hdl32();
  c.sensor.vertical_max_deg = -40.0;
  EXPECT_NE(std::string(c.validate().message()).find("lidar3d.vertical_max_deg"),
            std::string::npos);
  c = hdl32();
  c.sensor.noise_std_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(std::string(c.validate().message()).find("lidar3d.noise_std_m"), std::string::npos);
}

TEST(Lidar3dSimTest, RobotPresetsCarryAValidLidar3dBlock) {
  for (const char* name : {"pioneer3at", "campero"}) {
    loader::RobotSpec r;
    std::string error;
    ASSERT_TRUE(loader::load_robot_preset(
        std::string(CARRIL_SOURCE_DIR) + "/config/robots/" + name + ".yaml", r, error))
        << error;
    EXPECT_TRUE(r.lidar3d.present) << name;
    Lidar3dConfig c;
    c.sensor = r.lidar3d;
    EXPECT_TRUE(c.validate().is_ok()) << name << ": " << c.validate().message();
    EXPECT_EQ(r.lidar3d.rings, 32) << name;
  }
}

TEST(Lidar3dSimTest, LoaderRejectsABadLidar3dKeyNamingIt) {
  loader::RobotSpec r;
  std::string error;
  const std::string src = std::string(CARRIL_SOURCE_DIR) + "/config/robots/pioneer3at.yaml";
  std::ifstream in(src);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "rings: 32";
  const auto at = text.find(key, text.find("lidar3d:"));
  ASSERT_NE(at, std::string::npos);
  text.replace(at, key.size(), "rings: 0");
  const std::string path = ::testing::TempDir() + "lidar3d_bad_rings.yaml";
  std::ofstream(path) << text;
  EXPECT_FALSE(loader::load_robot_preset(path, r, error));
  EXPECT_NE(error.find("lidar3d.rings"), std::string::npos) << error;
  std::remove(path.c_str());
}

TEST(Lidar3dSimTest, SimPointCloudPublishesAndHonoursSilentAndFrozen) {
  hal::SimPointCloud dev;
  EXPECT_EQ(dev.latest(), nullptr);  // nothing yet
  Lidar3dSim sim(hdl32(), 1);
  FlatFloor floor;
  sim.render(floor, {}, 1, dev.back_buffer());
  dev.publish();
  ASSERT_NE(dev.latest(), nullptr);
  EXPECT_EQ(dev.latest()->seq, 1U);
  EXPECT_GT(dev.latest()->count, 0U);
  dev.inject_fault(hal::SimSensorFault::Frozen);
  sim.render(floor, {}, 2, dev.back_buffer());
  dev.publish();
  EXPECT_EQ(dev.latest()->seq, 1U);  // stuck on the old sweep
  dev.inject_fault(hal::SimSensorFault::None);
  sim.render(floor, {}, 3, dev.back_buffer());
  dev.publish();
  EXPECT_EQ(dev.latest()->seq, 3U);
  dev.inject_fault(hal::SimSensorFault::Silent);
  EXPECT_EQ(dev.latest(), nullptr);
}

}  // namespace
}  // namespace carril::sim
