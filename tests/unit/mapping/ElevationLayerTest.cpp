#include "firmware/mapping/ElevationLayer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "host_sim/alloc/AllocCounter.hpp"
#include "tests/unit/mapping/SyntheticTerrain.hpp"

namespace carril::fw {
namespace {

ElevationConfig small_config() {
  ElevationConfig c;
  c.size_x_m = c.size_y_m = 8.0;
  c.resolution_m = 0.05;
  c.min_range_m = 0.5;
  c.max_range_m = 10.0;
  return c;
}

Pose3 sensor_at(double x, double y, double z) {
  Pose3 p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

const ElevationCell& cell_at(const ElevationLayer& l, double x, double y) {
  int cx = 0, cy = 0;
  EXPECT_TRUE(l.grid().world_to_cell(x, y, cx, cy));
  return l.grid().at(cx, cy);
}

TEST(ElevationLayerTest, ConfigErrorsNameTheKey) {
  ElevationConfig c;
  c.noise_sigma_m = 0.0;
  EXPECT_NE(std::strstr(c.validate().message(), "elevation.noise_sigma_m"), nullptr);
  c = ElevationConfig{};
  c.max_range_m = 0.4;
  c.min_range_m = 0.5;
  EXPECT_NE(std::strstr(c.validate().message(), "max_range_m"), nullptr);
  EXPECT_TRUE(ElevationConfig{}.validate().is_ok());
  ElevationLayer l;
  c = ElevationConfig{};
  c.resolution_m = -1.0;
  EXPECT_FALSE(l.init(c).is_ok());
}

TEST(ElevationLayerTest, FlatFloorFromALidarSweep) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  l.recenter(0.0, 0.0);
  synth::render([](double, double) { return 0.0; }, 0.0, sensor_at(0, 0, 0.7), {}, *cloud);
  ASSERT_GT(cloud->count, 10000U);
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_GT(l.last_points_used(), 10000U);
  int observed = 0;
  for (int ly = 0; ly < l.grid().ny(); ++ly)
    for (int lx = 0; lx < l.grid().nx(); ++lx) {
      const ElevationCell& c = l.grid().local(lx, ly);
      if (!c.observed()) continue;
      ++observed;
      ASSERT_NEAR(c.height_m, 0.0F, 0.005F);
    }
  EXPECT_GT(observed, 3000);
  // The blind zone round the sensor stays unobserved.
  EXPECT_FALSE(cell_at(l, 0.3, 0.0).observed());
}

TEST(ElevationLayerTest, NonFiniteAndOutOfRangePointsAreSkipped) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  l.recenter(0.0, 0.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cloud->points[0] = {nan, 0.0F, -0.7F};
  cloud->points[1] = {1.0F, inf, -0.7F};
  cloud->points[2] = {1.0F, 0.0F, -inf};
  cloud->points[3] = {0.1F, 0.0F, -0.2F};   // inside the robot's body (min range)
  cloud->points[4] = {11.0F, 0.0F, -0.7F};  // beyond max range
  cloud->points[5] = {1.0F, 0.0F, -0.7F};   // the only good one
  cloud->points[6] = {nan, nan, nan};
  cloud->count = 7;
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_EQ(l.last_points_used(), 1U);
  EXPECT_EQ(l.last_cells_updated(), 1U);
  EXPECT_NEAR(cell_at(l, 1.02, 0.02).height_m, 0.0F, 1e-5F);
  // A non-finite pose fuses nothing.
  Pose3 bad = sensor_at(0, 0, 0.7);
  bad.pitch = double(nan);
  l.fuse(*cloud, bad);
  EXPECT_EQ(l.last_points_used(), 0U);
}

TEST(ElevationLayerTest, HighestPointOfASweepIsTheCellsMeasurement) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  l.recenter(0.0, 0.0);
  cloud->points[0] = {1.01F, 0.01F, -0.7F};
  cloud->points[1] = {1.02F, 0.02F, -0.4F};
  cloud->points[2] = {1.03F, 0.03F, -0.6F};
  cloud->count = 3;
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_EQ(l.last_cells_updated(), 1U);
  EXPECT_NEAR(cell_at(l, 1.02, 0.02).height_m, 0.3F, 1e-5F);
}

TEST(ElevationLayerTest, FusionReducesVarianceAndNoiseGrowsWithRange) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationConfig cfg = small_config();
  cfg.process_noise_m2_per_s = 0.0;
  ElevationLayer l;
  ASSERT_TRUE(l.init(cfg).is_ok());
  l.recenter(0.0, 0.0);
  cloud->points[0] = {1.0F, 0.0F, -0.70F};
  cloud->points[1] = {3.0F, 0.0F, -0.70F};
  cloud->count = 2;
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  const float v_near = cell_at(l, 1.0, 0.0).variance_m2;
  const float v_far = cell_at(l, 3.0, 0.0).variance_m2;
  EXPECT_GT(v_far, v_near);
  cloud->points[0] = {1.0F, 0.0F, -0.69F};
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  const ElevationCell& c = cell_at(l, 1.0, 0.0);
  EXPECT_NEAR(c.variance_m2, 0.5F * v_near, 2e-3F * v_near);  // two (almost) equal measurements
  EXPECT_NEAR(c.height_m, 0.005F, 1e-5F);                     // their mean
}

TEST(ElevationLayerTest, ProcessNoiseGrowsVarianceWithTime) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationConfig cfg = small_config();
  cfg.process_noise_m2_per_s = 0.001;
  ElevationLayer l;
  ASSERT_TRUE(l.init(cfg).is_ok());
  l.recenter(0.0, 0.0);
  cloud->points[0] = {1.0F, 0.0F, -0.70F};
  cloud->count = 1;
  cloud->stamp_ns = 1'000'000'000;
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  const float v0 = cell_at(l, 1.0, 0.0).variance_m2;
  cloud->count = 0;
  cloud->stamp_ns = 3'000'000'000;  // 2 s later, nothing seen
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_NEAR(cell_at(l, 1.0, 0.0).variance_m2, v0 + 0.002F, 1e-6F);
  EXPECT_FALSE(cell_at(l, 2.0, 0.0).observed());  // unobserved cells stay unobserved
}

// Something new stands on a well-known floor cell: the first sweep that sees it replaces the
// height. When it is gone again, the floor is re-learned within a few sweeps.
TEST(ElevationLayerTest, ANewObstacleReplacesTheFloorAndARemovedOneIsRelearned) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  l.recenter(0.0, 0.0);
  cloud->points[0] = {2.0F, 0.0F, -0.70F};
  cloud->count = 1;
  for (int i = 0; i < 10; ++i) l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_NEAR(cell_at(l, 2.0, 0.0).height_m, 0.0F, 1e-4F);
  cloud->points[0] = {2.0F, 0.0F, -0.20F};  // a 0.5 m box top
  l.fuse(*cloud, sensor_at(0, 0, 0.7));
  EXPECT_NEAR(cell_at(l, 2.0, 0.0).height_m, 0.5F, 1e-4F);
  cloud->points[0] = {2.0F, 0.0F, -0.70F};  // removed
  int sweeps = 0;
  while (cell_at(l, 2.0, 0.0).height_m > 0.05F && sweeps < 50) {
    l.fuse(*cloud, sensor_at(0, 0, 0.7));
    ++sweeps;
  }
  EXPECT_LE(sweeps, 5);
}

// The uncompensated mode ignores the sensor's pitch: a pitched sensor over flat ground then
// sees a slope; the compensated one sees the floor flat.
TEST(ElevationLayerTest, ImuAttitudeCompensation) {
  auto cloud = std::make_unique<hal::PointCloud>();
  Pose3 s = sensor_at(0, 0, 0.7);
  s.pitch = synth::deg(5.0);
  synth::render([](double, double) { return 0.0; }, 0.0, s, {}, *cloud);
  for (bool use : {true, false}) {
    ElevationConfig cfg = small_config();
    cfg.use_imu_attitude = use;
    ElevationLayer l;
    ASSERT_TRUE(l.init(cfg).is_ok());
    l.recenter(0.0, 0.0);
    l.fuse(*cloud, s);
    // Ahead (2 to 4 m): flat, or x * tan(5 deg) below when the pitch is ignored.
    int found = 0;
    for (double x = 2.0; x <= 4.0; x += 0.05)
      for (double y = -0.3; y <= 0.3; y += 0.05) {
        const ElevationCell& c = cell_at(l, x, y);
        if (!c.observed()) continue;
        ++found;
        const float expect = use ? 0.0F : float(-x * std::tan(synth::deg(5.0)));
        ASSERT_NEAR(c.height_m, expect, 0.03F) << "use_imu_attitude " << use << " x " << x;
      }
    EXPECT_GT(found, 10);
  }
}

// A sweep binned in pieces over several ticks gives the map fuse() gives in one; a sweep
// abandoned half way (a newer one began) leaves the map as it was.
TEST(ElevationLayerTest, ASweepInPiecesEqualsOneFuseAndAnAbandonedOneChangesNothing) {
  auto cloud = std::make_unique<hal::PointCloud>();
  synth::render(synth::ramp(1.0, 2.0, 5.0), 0.5, sensor_at(0, 0, 0.7), {}, *cloud);
  ASSERT_GT(cloud->count, 10000U);
  ElevationLayer whole, pieces;
  for (ElevationLayer* l : {&whole, &pieces}) {
    ASSERT_TRUE(l->init(small_config()).is_ok());
    l->recenter(0.0, 0.0);
  }
  const Pose3 s = sensor_at(0.02, -0.01, 0.7);
  for (int sweep = 0; sweep < 2; ++sweep) {
    cloud->stamp_ns += 200'000'000;
    whole.fuse(*cloud, s);
    // An abandoned start first: half its points binned, then a new begin.
    ASSERT_TRUE(pieces.begin_sweep(std::int64_t(cloud->stamp_ns), s));
    pieces.bin_points(*cloud, 0, cloud->count / 2);
    ASSERT_TRUE(pieces.begin_sweep(std::int64_t(cloud->stamp_ns), s));
    for (std::uint32_t first = 0; first < cloud->count; first += 4096)
      pieces.bin_points(*cloud, first, 4096);
    int steps = 1;
    ASSERT_FALSE(pieces.fuse_step(0));  // a step of nothing ages once, fuses nothing
    while (!pieces.fuse_step(500)) ++steps;
    EXPECT_GT(steps, 2);
  }
  EXPECT_EQ(pieces.last_points_used(), whole.last_points_used());
  EXPECT_EQ(pieces.last_cells_updated(), whole.last_cells_updated());
  int observed = 0;
  for (int ly = 0; ly < whole.grid().ny(); ++ly)
    for (int lx = 0; lx < whole.grid().nx(); ++lx) {
      const ElevationCell &a = whole.grid().local(lx, ly), &b = pieces.grid().local(lx, ly);
      ASSERT_EQ(a.observed(), b.observed());
      if (!a.observed()) continue;
      ++observed;
      ASSERT_EQ(a.height_m, b.height_m);
      ASSERT_EQ(a.variance_m2, b.variance_m2);
    }
  EXPECT_GT(observed, 1000);

  // Begun and binned but never ended: the map is untouched.
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  l.recenter(0.0, 0.0);
  ASSERT_TRUE(l.begin_sweep(1, s));
  l.bin_points(*cloud, 0, cloud->count);
  for (int ly = 0; ly < l.grid().ny(); ++ly)
    for (int lx = 0; lx < l.grid().nx(); ++lx) ASSERT_FALSE(l.grid().local(lx, ly).observed());
}

TEST(ElevationLayerTest, FuseDoesNotAllocate) {
  auto cloud = std::make_unique<hal::PointCloud>();
  ElevationLayer l;
  ASSERT_TRUE(l.init(small_config()).is_ok());
  synth::render(synth::ramp(1.0, 2.0, 5.0), 0.5, sensor_at(0, 0, 0.7), {}, *cloud);
  alloc::begin_window();
  for (int i = 0; i < 3; ++i) {
    cloud->stamp_ns += 100'000'000;
    l.recenter(0.1 * i, 0.0);
    l.fuse(*cloud, sensor_at(0.1 * i, 0, 0.7));
  }
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
  EXPECT_GT(alloc::count_total(), 0U);
}

}  // namespace
}  // namespace carril::fw
