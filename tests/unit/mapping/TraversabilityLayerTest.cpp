#include "firmware/mapping/TraversabilityLayer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/ElevationLayer.hpp"
#include "host_sim/alloc/AllocCounter.hpp"
#include "tests/unit/mapping/SyntheticTerrain.hpp"

namespace carril::fw {
namespace {

// Lidar sweep -> elevation -> terrain -> traversability, for a robot at `robot` on `surface`.
struct Pipeline {
  ElevationLayer elevation;
  TerrainAnalysis terrain;
  TraversabilityLayer trav;
  std::unique_ptr<hal::PointCloud> cloud = std::make_unique<hal::PointCloud>();

  explicit Pipeline(bool use_imu_attitude = true) {
    ElevationConfig ec;
    ec.size_x_m = ec.size_y_m = 10.0;
    ec.use_imu_attitude = use_imu_attitude;
    EXPECT_TRUE(elevation.init(ec).is_ok());
    const auto& g = elevation.grid();
    EXPECT_TRUE(terrain.init(TerrainConfig{}, g.nx(), g.ny(), g.resolution()).is_ok());
    EXPECT_TRUE(trav.init(g.nx(), g.ny(), g.resolution()).is_ok());
  }
  // The robot on the surface at (x, 0) heading +x, pitched `pitch_deg` (nose up).
  void see(const synth::Surface& s, double top, double x, double pitch_deg,
           const TraversabilityProfile& p) {
    Pose3Tracker t;
    t.reset(Pose2{x, 0.0, 0.0}, s(x, 0.0));
    t.update(Pose2{x, 0.0, 0.0}, 0.0F, float(synth::deg(pitch_deg)));
    SensorMount m;
    m.z_m = 0.7;
    const Pose3 sp = t.sensor_pose(m);
    synth::LidarPattern pat;
    pat.rings = 64;  // a denser sweep stands for a few accumulated ones
    synth::render(s, top, sp, pat, *cloud);
    elevation.recenter(x, 0.0);
    elevation.fuse(*cloud, sp);
    terrain.compute(elevation.grid());
    trav.update(terrain, p);
  }
  std::uint8_t cost(double x, double y) const {
    const auto& g = trav.grid();
    return g.at(g.cell_of(x), g.cell_of(y));
  }
  // Costs and slopes of the valid cells in [x0, x1] x [-0.5, 0.5].
  void collect(double x0, double x1, std::vector<std::uint8_t>& costs,
               std::vector<float>& slopes) const {
    const auto& g = trav.grid();
    for (int cx = g.cell_of(x0); cx <= g.cell_of(x1); ++cx)
      for (int cy = g.cell_of(-0.5); cy <= g.cell_of(0.5); ++cy) {
        const std::size_t i = terrain.index(cx - g.origin_cx(), cy - g.origin_cy());
        if (terrain.status()[i] != TerrainStatus::kValid) continue;
        costs.push_back(g.at(cx, cy));
        slopes.push_back(terrain.slope_rad()[i]);
      }
  }
};

double median_deg(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return double(v[v.size() / 2]) * 180.0 / kPi;
}

double fraction_lethal(const std::vector<std::uint8_t>& c) {
  return double(std::count(c.begin(), c.end(), cost::kLethal)) / double(c.size());
}

TEST(TraversabilityLayerTest, ProfileErrorsNameTheField) {
  TraversabilityProfile p;
  EXPECT_TRUE(p.validate().is_ok());
  p.max_step_down_m = 0.0;
  EXPECT_NE(std::strstr(p.validate().message(), "traversability.max_step_down_m"), nullptr);
  p = TraversabilityProfile{};
  p.graded_cost_max = 253;
  EXPECT_NE(std::strstr(p.validate().message(), "graded_cost_max"), nullptr);
}

TEST(TraversabilityLayerTest, ClassifyAgainstTheLimits) {
  const TraversabilityProfile p;  // 8 deg, 0.03 up, 0.10 down, graded up to 200
  const float d = float(kPi / 180.0);
  using TS = TerrainStatus;
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 0.0F, 0.0F, 0.0F, 0.0F, p), cost::kFree);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 4.0F * d, 0.0F, 0.0F, 0.0F, p), 100);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 8.5F * d, 0.0F, 0.0F, 0.0F, p),
            cost::kLethal);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 0.0F, 0.04F, 0.0F, 0.0F, p), cost::kLethal);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 0.0F, 0.0F, 0.08F, 0.0F, p), 160);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kValid, 0.0F, 0.0F, 0.0F, 0.2F, p), cost::kLethal);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kNotEnoughData, 0.0F, 0.3F, 0.0F, 0.0F, p),
            cost::kLethal);  // a step is known without a plane
  EXPECT_EQ(TraversabilityLayer::classify(TS::kNotEnoughData, 0.0F, 0.0F, 0.0F, 0.0F, p),
            cost::kUnknown);
  EXPECT_EQ(TraversabilityLayer::classify(TS::kUnobserved, 0.0F, 0.0F, 0.0F, 0.0F, p),
            cost::kUnknown);
}

// The thesis's ramps against pioneer3at's 8 deg: 10 deg lethal, 5 deg passable.
TEST(TraversabilityLayerTest, RampsOfFiveAndTenDegreesAgainstEight) {
  for (double angle : {5.0, 10.0}) {
    Pipeline pl;
    pl.see(synth::ramp(1.5, 3.0, angle), 0.6, 0.0, 0.0, TraversabilityProfile{});
    std::vector<std::uint8_t> costs;
    std::vector<float> slopes;
    pl.collect(2.0, 3.0, costs, slopes);
    ASSERT_GT(costs.size(), 50U) << angle;
    EXPECT_NEAR(median_deg(slopes), angle, 0.5) << angle;
    if (angle > 8.0)
      EXPECT_GT(fraction_lethal(costs), 0.9) << angle;
    else
      EXPECT_EQ(fraction_lethal(costs), 0.0) << angle;
  }
}

// A robot pitched 5 deg on a 5 deg ramp looks at an 11 deg ramp ahead. Without the IMU's
// attitude the map is tilted with the robot and the slope ahead reads 6 deg (passable); with it,
// 11 deg (lethal).
TEST(TraversabilityLayerTest, PitchCompensationOnARampPair) {
  const double t5 = std::tan(synth::deg(5.0)), t11 = std::tan(synth::deg(11.0));
  const synth::Surface pair = [=](double x, double) {
    if (x < -3.0) return 0.0;
    if (x < 3.0) return (x + 3.0) * t5;
    return 6.0 * t5 + (std::min(x, 5.0) - 3.0) * t11;
  };
  for (bool use : {true, false}) {
    Pipeline pl(use);
    pl.see(pair, 1.0, 1.5, 5.0, TraversabilityProfile{});
    std::vector<std::uint8_t> costs;
    std::vector<float> slopes;
    pl.collect(3.3, 4.5, costs, slopes);
    ASSERT_GT(costs.size(), 50U);
    EXPECT_NEAR(median_deg(slopes), use ? 11.0 : 6.0, 0.7) << "use_imu_attitude " << use;
    if (use)
      EXPECT_GT(fraction_lethal(costs), 0.9);
    else
      EXPECT_EQ(fraction_lethal(costs), 0.0);
  }
}

// A 20 cm drop 1.6 m ahead: the edge (upper side) is lethal, the hidden ground beyond unknown.
TEST(TraversabilityLayerTest, StepDownEdgeLethalAndBeyondUnknown) {
  Pipeline pl;
  pl.see(synth::step(1.6, -0.2), 0.0, 0.0, 0.0, TraversabilityProfile{});
  for (double y = -0.3; y <= 0.3; y += 0.05) {
    bool lethal = false;
    for (double x = 1.45; x < 1.6; x += 0.05)
      lethal = lethal || pl.cost(x + 0.01, y) == cost::kLethal;
    EXPECT_TRUE(lethal) << "y " << y;
    for (double x = 1.61; x < 1.9; x += 0.05) EXPECT_EQ(pl.cost(x, y), cost::kUnknown) << x;
  }
  EXPECT_TRUE(cost::passable(pl.cost(1.2, 0.0)));  // the flat ground before it
}

TEST(TraversabilityLayerTest, StartAreaIsFreeUntilObserved) {
  Pipeline pl;
  pl.trav.mark_start_free(0.0, 0.0, 1.0);
  EXPECT_EQ(pl.cost(0.0, 0.0), cost::kFree);
  EXPECT_EQ(pl.cost(1.5, 0.0), cost::kUnknown);
  pl.see(synth::box(0.0, 0.9, 0.3, 0.5), 0.5, 0.0, 0.0, TraversabilityProfile{});
  EXPECT_EQ(pl.cost(0.0, 0.0), cost::kFree);       // under the robot: never seen
  EXPECT_EQ(pl.cost(0.0, 0.77), cost::kLethal);    // the box face, seen inside the start area
  EXPECT_EQ(pl.cost(-3.0, -3.0), cost::kUnknown);  // outside it, unseen
  // Moved away and back: the mask is remembered in the odometry frame.
  pl.see(synth::box(0.0, 0.9, 0.3, 0.5), 0.5, 3.0, 0.0, TraversabilityProfile{});
  EXPECT_EQ(pl.cost(0.0, 0.0), cost::kFree);
}

TEST(TraversabilityLayerTest, UpdateDoesNotAllocate) {
  Pipeline pl;
  pl.see(synth::ramp(1.5, 3.0, 5.0), 0.6, 0.0, 0.0, TraversabilityProfile{});
  alloc::begin_window();
  pl.trav.update(pl.terrain, TraversabilityProfile{});
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
}

}  // namespace
}  // namespace carril::fw
