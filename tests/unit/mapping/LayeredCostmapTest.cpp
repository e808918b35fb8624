#include "firmware/mapping/LayeredCostmap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

CostmapConfig small_config() {
  CostmapConfig c;
  c.size_x_m = 6.0;
  c.size_y_m = 4.0;
  c.resolution_m = 0.05;
  c.inflation.inscribed_radius_m = 0.2;
  c.inflation.inflation_radius_m = 0.4;
  return c;
}

TEST(LayeredCostmapTest, InitRejectsBadConfigNamingTheKey) {
  LayeredCostmap cm;
  CostmapConfig c = small_config();
  c.resolution_m = 0.0;
  Status s = cm.init(c);
  EXPECT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("costmap.resolution_m"), std::string::npos);
  c = small_config();
  c.obstacle.raytrace_max_range_m = -1.0;
  s = cm.init(c);
  EXPECT_NE(std::string(s.message()).find("raytrace_max_range_m"), std::string::npos);
  c = small_config();
  c.size_x_m = 100.0;  // 2000 cells
  EXPECT_NE(std::string(cm.init(c).message()).find("size_x_m"), std::string::npos);
  EXPECT_TRUE(cm.init(small_config()).is_ok());
  EXPECT_EQ(cm.master().nx(), 120);
  EXPECT_EQ(cm.master().ny(), 80);
  EXPECT_TRUE(CostmapConfig{}.validate().is_ok());
  EXPECT_EQ(CostmapConfig{}.nx(), 240);
}

// The combination rule, cell by cell, on cells far from any lethal cell (no inflation there).
TEST(LayeredCostmapTest, CombinesLayersByTheRule) {
  LayeredCostmap cm;
  ASSERT_TRUE(cm.init(small_config()).is_ok());
  cm.recenter(0.0, 0.0);
  RollingGrid<std::uint8_t> extra;
  ASSERT_TRUE(extra.init(120, 80, 0.05, cost::kUnknown));
  extra.recenter(0.0, 0.0);
  // Obstacle layer: a beam along +x from the origin frees row 0 up to a hit at 2 m.
  hal::LaserScan s;
  s.count = 1;
  s.range_max_m = 10.0F;
  s.ranges_m[0] = 2.0F;
  cm.update_obstacles(s, Pose2{0.025, 0.025, 0.0});
  ASSERT_EQ(cm.obstacle_layer().at(40, 0), cost::kLethal);
  ASSERT_EQ(cm.obstacle_layer().at(5, 0), cost::kFree);
  extra.at(5, 0) = cost::kUnknown;      // free + unknown -> free
  extra.at(-30, 20) = 100;              // unknown + 100 -> 100
  extra.at(-20, -20) = cost::kUnknown;  // unknown + unknown -> unknown
  extra.at(0, -30) = cost::kLethal;     // unknown + lethal -> lethal
  extra.at(40, 0) = cost::kFree;        // lethal + free -> lethal
  extra.at(20, 0) = 60;                 // free + 60 -> 60
  const RollingGrid<std::uint8_t>* layers[] = {&extra};
  EXPECT_TRUE(cm.update_master(layers, 1));
  const auto& m = cm.master();
  EXPECT_EQ(m.at(5, 0), cost::kFree);
  EXPECT_EQ(m.at(-30, 20), 100);
  EXPECT_EQ(m.at(-20, -20), cost::kUnknown);
  EXPECT_EQ(m.at(0, -30), cost::kLethal);
  EXPECT_EQ(m.at(40, 0), cost::kLethal);
  EXPECT_EQ(m.at(20, 0), 60);
  // And then inflated: next to each lethal cell, inscribed.
  EXPECT_EQ(m.at(0, -29), cost::kInscribed);
  EXPECT_EQ(m.at(39, 0), cost::kInscribed);
  EXPECT_EQ(m.at(40, 3), cost::kInscribed);  // was unknown in both layers
  // Without the extra layer, its cells are gone from the master.
  EXPECT_TRUE(cm.update_master());
  EXPECT_EQ(m.at(-30, 20), cost::kUnknown);
  EXPECT_EQ(m.at(0, -30), cost::kUnknown);
}

TEST(LayeredCostmapTest, SkipsAnExtraLayerOfAnotherWindow) {
  LayeredCostmap cm;
  ASSERT_TRUE(cm.init(small_config()).is_ok());
  RollingGrid<std::uint8_t> moved;
  ASSERT_TRUE(moved.init(120, 80, 0.05, cost::kLethal));
  moved.recenter(1.0, 0.0);
  const RollingGrid<std::uint8_t>* layers[] = {&moved, nullptr};
  EXPECT_FALSE(cm.update_master(layers, 2));
  EXPECT_EQ(cm.master().local(10, 10), cost::kUnknown);
}

TEST(LayeredCostmapTest, QueriesByWorldPointAndFootprint) {
  LayeredCostmap cm;
  ASSERT_TRUE(cm.init(small_config()).is_ok());
  cm.recenter(0.0, 0.0);
  hal::LaserScan s;
  s.count = 1;
  s.range_max_m = 10.0F;
  s.ranges_m[0] = 2.0F;
  cm.update_obstacles(s, Pose2{0.025, 0.025, 0.0});  // lethal cell (40, 0): x in [2.0, 2.05)
  cm.update_master();
  EXPECT_EQ(cm.cost_at_world(2.02, 0.01), cost::kLethal);
  EXPECT_EQ(cm.cost_at_world(1.0, 0.01), cost::kFree);
  EXPECT_EQ(cm.cost_at_world(50.0, 0.0), cost::kUnknown);
  EXPECT_EQ(cm.cost_at_world(std::nan(""), 0.0), cost::kUnknown);
  // A 0.6 x 0.2 m rectangle whose front edge passes the lethal cell's centre (2.025), then one
  // whose edge stops 5 cm short of it (only inflation under it), then a 0.02 x 0.6 m one turned
  // 90 deg lying on the free row.
  EXPECT_EQ(cm.footprint_cost(Pose2{1.73, 0.025, 0.0}, 0.3, 0.01), cost::kLethal);
  EXPECT_EQ(cm.footprint_cost(Pose2{1.68, 0.025, 0.0}, 0.3, 0.01), cost::kInscribed);
  EXPECT_EQ(cm.footprint_cost(Pose2{1.0, 0.025, kPi / 2}, 0.01, 0.3), cost::kFree);
  EXPECT_EQ(cm.footprint_cost(Pose2{1.0, 0.025, 0.0}, 0.03, 0.3), cost::kUnknown);  // rows off 0
  // A thin rectangle at 45 deg whose axis runs through the lethal cell's centre: lethal only if
  // the rotation is applied.
  EXPECT_EQ(cm.footprint_cost(Pose2{1.8, -0.2, kPi / 4}, 0.4, 0.02), cost::kLethal);
  // Half outside the window: unknown.
  EXPECT_EQ(cm.footprint_cost(Pose2{-2.9, 0.025, 0.0}, 0.3, 0.1), cost::kUnknown);
}

TEST(LayeredCostmapTest, TickDoesNotAllocate) {
  LayeredCostmap cm;
  ASSERT_TRUE(cm.init(CostmapConfig{}).is_ok());
  RollingGrid<std::uint8_t> extra;
  ASSERT_TRUE(extra.init(240, 240, 0.05, cost::kUnknown));
  hal::LaserScan s;
  s.count = 541;
  s.angle_min_rad = -2.356F;
  s.angle_increment_rad = 0.00872F;
  s.range_max_m = 10.0F;
  for (int i = 0; i < 541; ++i) s.ranges_m[std::size_t(i)] = 1.0F + float(i % 50) * 0.1F;
  const RollingGrid<std::uint8_t>* layers[] = {&extra};
  alloc::begin_window();
  for (int k = 0; k < 3; ++k) {
    cm.recenter(0.3 * k, 0.1 * k);
    extra.recenter(0.3 * k, 0.1 * k);
    cm.update_obstacles(s, Pose2{0.3 * k, 0.1 * k, 0.2 * k});
    cm.update_master(layers, 1);
    (void)cm.footprint_cost(Pose2{0.3 * k, 0.0, 0.0}, 0.4, 0.3);
  }
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
}

}  // namespace
}  // namespace carril::fw
