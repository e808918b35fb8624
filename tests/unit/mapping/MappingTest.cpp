// The Mapping component with terrain: a 3D sweep goes through the cycle in bounded pieces (bin,
// fuse, analyse, combine), and the result equals the whole computation done at once; no master
// is published before the first cycle completes; a sweep replaced while it is being binned is
// abandoned, and nothing of it reaches the map. On a known map: scans are marked only while the
// pose is localised, and a relocalisation (the pose may have jumped) forgets the obstacle layer.
#include "firmware/mapping/Mapping.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "tests/unit/mapping/SyntheticTerrain.hpp"

namespace carril::fw {
namespace {

constexpr double kRateHz = 100.0;
constexpr hal::TimeNs kTickNs = 10'000'000;

MappingConfig terrain_config() {
  MappingConfig c;
  c.enabled = true;
  c.terrain = true;
  c.lidar3d.z_m = 0.7;
  return c;
}

// A 20 cm step 2 m ahead and a 1 m box to the left, seen from the sensor 0.7 m up.
double scene(double x, double y) {
  return (x > 2.0 ? 0.2 : 0.0) + synth::box(0.5, 2.0, 1.0, 1.0)(x, y);
}

struct Rig {
  MappingConfig cfg = terrain_config();
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom;
  std::unique_ptr<Mapping> mapping;
  hal::TimeNs now = 0;

  Rig() {
    EXPECT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
    mapping = std::make_unique<Mapping>(cfg, kRateHz, Pose2{}, frame, odom);
  }
  void tick(const hal::PointCloud* cloud) {
    now += kTickNs;
    frame.edit().now_ns = now;
    frame.edit().cloud = cloud;
    frame.publish(now);
    odom.publish(OdometryMsg{}, now);
    mapping->run();
  }
};

std::unique_ptr<hal::PointCloud> sweep(const synth::Surface& s, std::uint32_t seq,
                                       hal::TimeNs stamp) {
  auto c = std::make_unique<hal::PointCloud>();
  Pose3 sensor;
  sensor.z = 0.7;
  synth::LidarPattern pat;
  pat.step_m = 0.02;
  synth::render(s, 1.0, sensor, pat, *c);
  c->seq = seq;
  c->stamp_ns = stamp;
  return c;
}

TEST(MappingTest, ATerrainCycleInPiecesEqualsTheWholeComputation) {
  Rig r;
  const auto cloud = sweep(scene, 1, kTickNs);
  ASSERT_GT(cloud->count, 40000U);
  int ticks = 0;
  while (r.mapping->updates() == 0 && ticks < 1000) {
    r.tick(cloud.get());
    ++ticks;
  }
  ASSERT_EQ(r.mapping->updates(), 1U);
  // Spread: at least the binning, fusing and strips, one piece a tick.
  const int min_ticks =
      int(cloud->count) / r.cfg.fuse_points_per_tick + 240 / r.cfg.terrain_rows_per_tick;
  EXPECT_GE(ticks, min_ticks);

  // The same sweep fused, analysed and classified whole.
  ElevationLayer elevation;
  ASSERT_TRUE(elevation.init(r.cfg.elevation).is_ok());
  elevation.recenter(0.0, 0.0);
  Pose3 sensor;
  sensor.z = 0.7;
  elevation.fuse(*cloud, sensor);
  TerrainAnalysis analysis;
  ASSERT_TRUE(analysis.init(r.cfg.analysis, 240, 240, 0.05).is_ok());
  analysis.compute(elevation.grid());
  TraversabilityLayer trav;
  ASSERT_TRUE(trav.init(240, 240, 0.05).is_ok());
  trav.mark_start_free(0.0, 0.0, r.cfg.start_free_radius_m);
  trav.update(analysis, r.cfg.profile);

  const RollingGrid<std::uint8_t>& got = r.mapping->traversability().grid();
  ASSERT_EQ(got.origin_cx(), trav.grid().origin_cx());
  ASSERT_EQ(got.origin_cy(), trav.grid().origin_cy());
  int lethal = 0;
  for (int ly = 0; ly < 240; ++ly)
    for (int lx = 0; lx < 240; ++lx) {
      ASSERT_EQ(got.local(lx, ly), trav.grid().local(lx, ly)) << lx << ", " << ly;
      lethal += got.local(lx, ly) == cost::kLethal ? 1 : 0;
    }
  EXPECT_GT(lethal, 100);  // the step edge and the box are in it
  EXPECT_EQ(r.mapping->telemetry().sweeps, 1U);
}

TEST(MappingTest, NoMasterBeforeTheFirstTerrainCycleThenAtTheMasterRate) {
  Rig r;
  const auto cloud = sweep(scene, 1, kTickNs);
  int first = -1;
  for (int t = 0; t < 400; ++t) {
    r.tick(cloud.get());
    if (first < 0 && r.mapping->updates() > 0) first = t;
  }
  ASSERT_GT(first, 50);  // only once the cycle is complete
  // Then the master is rebuilt at master_rate_hz (5 Hz) although no new sweep arrives.
  const double expected = (400 - first) / (kRateHz / r.cfg.master_rate_hz);
  EXPECT_NEAR(double(r.mapping->updates()), 1.0 + expected, 2.0);
  EXPECT_EQ(r.mapping->telemetry().sweeps, 1U);
}

TEST(MappingTest, ASweepReplacedWhileBinningIsAbandoned) {
  Rig r;
  const auto old_sweep = sweep(scene, 1, kTickNs);
  const auto flat = sweep([](double, double) { return 0.0; }, 2, 3 * kTickNs);
  r.tick(old_sweep.get());  // begins binning the old one
  r.tick(old_sweep.get());
  r.tick(old_sweep.get());
  int ticks = 0;
  while (r.mapping->updates() == 0 && ticks < 1000) {
    r.tick(flat.get());  // the driver has moved on
    ++ticks;
  }
  EXPECT_EQ(r.mapping->telemetry().sweeps_abandoned, 1U);
  EXPECT_EQ(r.mapping->telemetry().sweeps, 1U);
  // Nothing of the old sweep: no cell of the box or above the step.
  const RollingGrid<ElevationCell>& g = r.mapping->elevation().grid();
  int observed = 0;
  for (int ly = 0; ly < g.ny(); ++ly)
    for (int lx = 0; lx < g.nx(); ++lx) {
      const ElevationCell& c = g.local(lx, ly);
      if (!c.observed()) continue;
      ++observed;
      ASSERT_LT(c.height_m, 0.05F) << lx << ", " << ly;
    }
  EXPECT_GT(observed, 1000);
}

// One return, `range` away along `angle` from a sensor at the robot centre.
hal::LaserScan one_beam(std::uint32_t seq, double angle, double range) {
  hal::LaserScan s;
  s.seq = seq;
  s.count = 1;
  s.angle_min_rad = float(angle);
  s.angle_increment_rad = 0.01F;
  s.range_min_m = 0.05F;
  s.range_max_m = 8.0F;
  s.ranges_m[0] = float(range);
  return s;
}

TEST(MappingTest, OnAMapScansMarkOnlyWhileLocalisedAndARelocalisationForgetsTheMarks) {
  // A 4 x 4 m free square at 0.05 m, walls on its border.
  MapInfo info{80, 80, 0.05, -2.0, -2.0};
  std::vector<std::uint8_t> cells(80 * 80, cost::kFree);
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 80; ++i)
      if (i == 0 || j == 0 || i == 79 || j == 79) cells[std::size_t(j * 80 + i)] = cost::kLethal;
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  MappingConfig cfg;
  cfg.enabled = true;
  ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> pose;
  Mapping m(cfg, kRateHz, Pose2{}, frame, pose, &map);
  ASSERT_TRUE(m.on_map());
  hal::TimeNs now = 0;
  auto tick = [&](const hal::LaserScan* scan, bool localised, std::uint32_t relocalisations) {
    now += kTickNs;
    frame.edit().now_ns = now;
    frame.edit().scan = scan;
    frame.publish(now);
    OdometryMsg p;
    p.localised = localised;
    p.relocalisations = relocalisations;
    pose.publish(p, now);
    m.run();
  };
  auto lethal = [&](const RollingGrid<std::uint8_t>& g, double x, double y) {
    int cx = 0, cy = 0;
    return g.world_to_cell(x, y, cx, cy) && g.at(cx, cy) == cost::kLethal;
  };
  // Localised: a return 1 m ahead marks its cell, and the master shows it at its next rebuild.
  const hal::LaserScan ahead = one_beam(1, 0.0, 1.0);
  for (int k = 0; k < 25; ++k) tick(&ahead, true, 0);
  EXPECT_TRUE(lethal(m.obstacles(), 1.0, 0.0));
  EXPECT_TRUE(lethal(m.master(), 1.0, 0.0));
  // Not localised: a scan is not marked (counted), the old mark stays.
  const hal::LaserScan left = one_beam(2, 0.5 * kPi, 1.0);
  tick(&left, false, 0);
  EXPECT_FALSE(lethal(m.obstacles(), 0.0, 1.0));
  EXPECT_TRUE(lethal(m.obstacles(), 1.0, 0.0));
  EXPECT_EQ(m.telemetry().scans_unlocalised, 1U);
  EXPECT_EQ(m.telemetry().obstacle_clears, 0U);
  // Localised again after being lost: the layer is forgotten, in the master the same tick (a
  // mission replanning on the jump reads it next); the walls of the map stay.
  tick(&left, true, 1);
  EXPECT_FALSE(lethal(m.obstacles(), 1.0, 0.0));
  EXPECT_FALSE(lethal(m.master(), 1.0, 0.0));
  EXPECT_TRUE(lethal(m.master(), -2.0 + 0.025, 0.0));
  EXPECT_EQ(m.telemetry().obstacle_clears, 1U);
  // Once: the same count does not clear again, and new scans mark again.
  const hal::LaserScan ahead2 = one_beam(3, 0.0, 1.0);
  for (int k = 0; k < 25; ++k) tick(&ahead2, true, 1);
  EXPECT_TRUE(lethal(m.obstacles(), 1.0, 0.0));
  EXPECT_EQ(m.telemetry().obstacle_clears, 1U);
}

}  // namespace
}  // namespace carril::fw
