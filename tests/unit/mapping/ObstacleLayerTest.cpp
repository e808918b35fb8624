#include "firmware/mapping/ObstacleLayer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

constexpr double kRes = 0.1;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kDeg = kPi / 180.0;

// A 16 m x 16 m window at 0.1 m centred on the origin: cells [-80, 80).
ObstacleLayer make_layer(ObstacleLayerConfig cfg = {}) {
  ObstacleLayer layer;
  EXPECT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  EXPECT_TRUE(layer.init(cfg, 160, 160, kRes));
  layer.recenter(0.0, 0.0);
  return layer;
}

// n beams from angle_min [rad] every inc [rad], all at range r [m].
hal::LaserScan make_scan(int n, double angle_min, double inc, float r, std::int64_t stamp_ns = 0) {
  hal::LaserScan s;
  s.seq = 1;
  s.stamp_ns = stamp_ns;
  s.angle_min_rad = float(angle_min);
  s.angle_increment_rad = float(inc);
  s.range_min_m = 0.05F;
  s.range_max_m = 10.0F;
  s.count = std::uint16_t(n);
  for (int i = 0; i < n; ++i) s.ranges_m[std::size_t(i)] = r;
  return s;
}

std::uint8_t at_world(const ObstacleLayer& l, double x, double y) {
  int cx = 0, cy = 0;
  if (!l.grid().world_to_cell(x, y, cx, cy)) return 200;  // a value the layer never writes
  return l.grid().at(cx, cy);
}

// The sensor sits at a cell centre so that beams along the axes stay in one row.
const Pose2 kOrigin{0.05, 0.05, 0.0};

TEST(ObstacleLayerTest, HitMarksAndTheRayClears) {
  ObstacleLayer l = make_layer();
  const auto st = l.update(make_scan(1, 0.0, 0.0, 2.0F), kOrigin);
  EXPECT_EQ(st.marked, 1);
  EXPECT_EQ(l.grid().at(20, 0), cost::kLethal);
  for (int cx = 0; cx < 20; ++cx) EXPECT_EQ(l.grid().at(cx, 0), cost::kFree) << cx;
  EXPECT_EQ(l.grid().at(21, 0), cost::kUnknown);
  EXPECT_EQ(l.grid().at(-1, 0), cost::kUnknown);
  EXPECT_EQ(l.grid().at(10, 1), cost::kUnknown);
  // A return beyond the marking range (5 m) clears up to it but marks nothing, and keeps its
  // own cell.
  l.update(make_scan(1, kPi / 2, 0.0, 5.5F), kOrigin);
  for (int cy = 0; cy < 55; ++cy) EXPECT_EQ(l.grid().at(0, cy), cost::kFree) << cy;
  EXPECT_EQ(l.grid().at(0, 55), cost::kUnknown);
}

TEST(ObstacleLayerTest, InfinityClearsToTheClearingRange) {
  ObstacleLayerConfig cfg;
  cfg.raytrace_max_range_m = 6.0;
  ObstacleLayer l = make_layer(cfg);
  l.update(make_scan(1, 0.0, 0.0, kInf), kOrigin);
  for (int cx = 0; cx <= 60; ++cx) EXPECT_EQ(l.grid().at(cx, 0), cost::kFree) << cx;
  EXPECT_EQ(l.grid().at(61, 0), cost::kUnknown);
  // Beyond range_max is "nothing within range_max": the same.
  l.update(make_scan(1, kPi, 0.0, 12.0F), kOrigin);
  for (int cx = -60; cx <= 0; ++cx) EXPECT_EQ(l.grid().at(cx, 0), cost::kFree) << cx;
  EXPECT_EQ(l.grid().at(-61, 0), cost::kUnknown);
}

TEST(ObstacleLayerTest, GarbageRangesChangeNothing) {
  ObstacleLayer l = make_layer();
  hal::LaserScan s = make_scan(6, -0.5, 0.2, 1.0F);
  s.ranges_m[0] = std::numeric_limits<float>::quiet_NaN();
  s.ranges_m[1] = 0.0F;
  s.ranges_m[2] = -kInf;
  s.ranges_m[3] = -1.0F;
  s.ranges_m[4] = 0.01F;  // below range_min
  s.ranges_m[5] = std::numeric_limits<float>::signaling_NaN();
  const auto st = l.update(s, kOrigin);
  EXPECT_EQ(st.ignored, 6);
  EXPECT_EQ(st.marked + st.cleared, 0);
  // A usable scan from an unusable pose or with unusable angles: nothing either.
  const hal::LaserScan good = make_scan(10, -0.5, 0.1, 1.0F);
  EXPECT_EQ(l.update(good, Pose2{std::nan(""), 0.0, 0.0}).ignored, 10);
  hal::LaserScan bad_angles = good;
  bad_angles.angle_increment_rad = kInf;
  EXPECT_EQ(l.update(bad_angles, kOrigin).ignored, 10);
  for (int ly = 0; ly < l.grid().ny(); ++ly)
    for (int lx = 0; lx < l.grid().nx(); ++lx) ASSERT_EQ(l.grid().local(lx, ly), cost::kUnknown);
}

TEST(ObstacleLayerTest, ObstacleOutsideTheFieldOfViewIsKept) {
  ObstacleLayer l = make_layer();
  // Facing -x: a 180 deg scan sees a post 2 m behind the robot's later heading.
  hal::LaserScan s = make_scan(181, -90 * kDeg, kDeg, kInf);
  s.ranges_m[90] = 2.0F;
  l.update(s, Pose2{0.05, 0.05, kPi});
  ASSERT_EQ(at_world(l, -1.95, 0.05), cost::kLethal);
  // Turned to +x, 50 scans of free space ahead: the post behind is not seen, so it stays.
  for (int i = 0; i < 50; ++i) l.update(make_scan(181, -90 * kDeg, kDeg, kInf), kOrigin);
  EXPECT_EQ(at_world(l, -1.95, 0.05), cost::kLethal);
  EXPECT_EQ(at_world(l, 1.95, 0.05), cost::kFree);
}

TEST(ObstacleLayerTest, RemovedObstacleClearsAfterClearScansScansNotOne) {
  ObstacleLayerConfig cfg;
  cfg.clear_scans = 3;
  ObstacleLayer l = make_layer(cfg);
  // 0.1 deg beams: about 50 beams of one scan cross the cell 1 m ahead.
  constexpr int kBeams = 601;
  hal::LaserScan hit = make_scan(kBeams, -30 * kDeg, 0.1 * kDeg, kInf);
  hit.ranges_m[300] = 1.0F;
  const hal::LaserScan open = make_scan(kBeams, -30 * kDeg, 0.1 * kDeg, kInf);
  l.update(hit, kOrigin);
  ASSERT_EQ(l.grid().at(10, 0), cost::kLethal);
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kLethal) << "cleared by one scan";
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kLethal);
  // A hit re-arms the count: three more free scans are needed.
  l.update(hit, kOrigin);
  l.update(open, kOrigin);
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kLethal);
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kFree);
}

// A beam that walks the same cells as the one before it is skipped within a scan, but each scan
// walks its own: the same single beam, scan after scan, counts one miss each time.
TEST(ObstacleLayerTest, TheSameBeamEveryScanCountsAMissEveryScan) {
  ObstacleLayerConfig cfg;
  cfg.clear_scans = 3;
  ObstacleLayer l = make_layer(cfg);
  l.update(make_scan(1, 0.0, 0.0, 1.0F), kOrigin);
  ASSERT_EQ(l.grid().at(10, 0), cost::kLethal);
  const hal::LaserScan open = make_scan(1, 0.0, 0.0, kInf);
  l.update(open, kOrigin);
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kLethal) << "cleared by two scans";
  l.update(open, kOrigin);
  EXPECT_EQ(l.grid().at(10, 0), cost::kFree);
}

// Rays from the sensor skip the cells of the square round it that were free as the scan began
// (ObstacleLayer::free_radius). An obstacle at the edge of that square must still be crossed: a
// lethal cell 1 to 30 cells from the sensor, on the axes, the diagonals and between them in
// every octant, inside a cleared disc, is cleared by one open scan (clear_scans 1). One step
// skipped too many leaves it lethal.
TEST(ObstacleLayerTest, RaysStillCrossAnObstacleAtTheEdgeOfTheFreeSquareRoundTheSensor) {
  ObstacleLayerConfig cfg;
  cfg.clear_scans = 1;
  cfg.raytrace_max_range_m = 6.0;
  const hal::LaserScan open = make_scan(2000, -kPi, 2.0 * kPi / 2000.0, kInf);
  int checked = 0;
  for (const int d : {1, 2, 3, 7, 10, 30}) {
    // (major, minor) offsets, then every sign and both axes as the major one.
    const int offsets[][2] = {{d, 0}, {d, d}, {d, d / 2}, {d, 1}, {d, d - 1}};
    for (const auto& off : offsets) {
      for (int o = 0; o < 8; ++o) {
        const int sa = (o & 1) != 0 ? -1 : 1, sb = (o & 2) != 0 ? -1 : 1;
        const int cx = o >= 4 ? sa * off[0] : sb * off[1];
        const int cy = o >= 4 ? sb * off[1] : sa * off[0];
        ObstacleLayer l = make_layer(cfg);
        l.update(open, kOrigin);
        // The disc within 4 m is free: the free square round the sensor is as large as it gets.
        for (int x = -28; x <= 28; ++x) {
          for (int y = -28; y <= 28; ++y) ASSERT_EQ(l.grid().at(x, y), cost::kFree);
        }
        // A hit at the centre of cell (cx, cy) marks it.
        const double a = std::atan2(double(cy), double(cx));
        const double r = std::hypot(double(cx), double(cy)) * kRes;
        l.update(make_scan(1, a, 0.0, float(r)), kOrigin);
        ASSERT_EQ(l.grid().at(cx, cy), cost::kLethal) << "cell (" << cx << ", " << cy << ")";
        l.update(open, kOrigin);
        EXPECT_EQ(l.grid().at(cx, cy), cost::kFree) << "not crossed: (" << cx << ", " << cy << ")";
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 6 * 5 * 8);
}

// The free-square skip against the walk of every cell, on random scans: a robot driving and
// turning among random obstacles, its scans with random returns, +inf, NaN and short ranges, the
// window moving with it. Both layers must hold the same cells after every scan.
TEST(ObstacleLayerTest, SkippingTheFreeSquareGivesWhatWalkingEveryCellGives) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int scans = 0, skipped_far = 0;  // scans whose rays skipped 5 steps or more
  for (int world = 0; world < 16; ++world) {
    ObstacleLayerConfig cfg;
    cfg.clear_scans = 1 + world % 3;
    cfg.raytrace_max_range_m = world % 2 == 0 ? 6.0 : 3.0;
    ObstacleLayer fast = make_layer(cfg), ref = make_layer(cfg);
    ref.walk_every_cell(true);
    Pose2 pose{u(rng), u(rng), u(rng) * 2.0 * kPi};
    for (int k = 0; k < 60; ++k) {
      // A 360 deg scanner in half the worlds, 270 deg (blind behind) in the others.
      const int n = world % 4 < 2 ? 720 : 541;
      const double start = world % 4 < 2 ? -kPi : -135 * kDeg;
      hal::LaserScan s = make_scan(n, start, 0.5 * kDeg, kInf, std::int64_t(k) * 50'000'000);
      // Obstacles at random bearings and ranges, the rest open; some garbage.
      for (int b = 0; b < n; ++b) {
        const double p = u(rng);
        if (p < 0.3) s.ranges_m[std::size_t(b)] = float(0.8 + 6.0 * u(rng));
        if (p > 0.99) s.ranges_m[std::size_t(b)] = std::numeric_limits<float>::quiet_NaN();
      }
      // A run of beams on one obstacle, now and then a few cells from the sensor.
      const int b0 = int(u(rng) * n), len = int(u(rng) * 60);
      const float wall = float((k % 4 == 0 ? 0.15 : 0.6) + 1.5 * u(rng));
      for (int b = b0; b < std::min(n, b0 + len); ++b) s.ranges_m[std::size_t(b)] = wall;
      fast.update(s, pose);
      ref.update(s, pose);
      for (int cy = fast.grid().origin_cy(); cy < fast.grid().origin_cy() + 160; ++cy) {
        for (int cx = fast.grid().origin_cx(); cx < fast.grid().origin_cx() + 160; ++cx) {
          ASSERT_EQ(fast.grid().at(cx, cy), ref.grid().at(cx, cy))
              << "world " << world << " scan " << k << " cell (" << cx << ", " << cy << ")";
        }
      }
      ++scans;
      // Drive on: 0.1 to 0.3 m, turning, the window following now and then.
      const double step = 0.1 + 0.2 * u(rng);
      pose = {pose.x + step * std::cos(pose.yaw), pose.y + step * std::sin(pose.yaw),
              pose.yaw + (u(rng) - 0.5)};
      if (k % 7 == 0) {
        fast.recenter(pose.x, pose.y);
        ref.recenter(pose.x, pose.y);
      }
      if (fast.skipped_steps() >= 5) ++skipped_far;
      EXPECT_EQ(ref.skipped_steps(), 0);
    }
  }
  EXPECT_EQ(scans, 16 * 60);
  EXPECT_GT(skipped_far, 100) << "the free square was rarely 5 cells or more";
}

TEST(ObstacleLayerTest, DecayForgetsUnconfirmedObstacles) {
  ObstacleLayerConfig cfg;
  cfg.decay_s = 1.0;
  ObstacleLayer l = make_layer(cfg);
  l.update(make_scan(1, 0.0, 0.0, 2.0F, 0), kOrigin);
  ASSERT_EQ(l.grid().at(20, 0), cost::kLethal);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  l.update(make_scan(1, 0.0, 0.0, nan, 500'000'000), kOrigin);
  EXPECT_EQ(l.grid().at(20, 0), cost::kLethal);
  l.update(make_scan(1, 0.0, 0.0, nan, 1'100'000'000), kOrigin);
  EXPECT_EQ(l.grid().at(20, 0), cost::kUnknown);
  EXPECT_EQ(l.grid().at(10, 0), cost::kFree);  // free cells do not decay
}

TEST(ObstacleLayerTest, MovingTheWindowKeepsCells) {
  ObstacleLayer l = make_layer();
  l.update(make_scan(1, 0.0, 0.0, 2.0F), kOrigin);
  l.recenter(1.3, -0.7);
  EXPECT_EQ(l.grid().origin_cx(), 13 - 80);
  EXPECT_EQ(l.grid().at(20, 0), cost::kLethal);
  EXPECT_EQ(l.grid().at(5, 0), cost::kFree);
  // And rays work in the moved window across the storage seam.
  l.update(make_scan(1, kPi / 2, 0.0, 3.0F), Pose2{1.35, 0.05, 0.0});
  EXPECT_EQ(at_world(l, 1.35, 3.05), cost::kLethal);
  EXPECT_EQ(at_world(l, 1.35, 1.55), cost::kFree);
}

TEST(ObstacleLayerTest, RaysLeavingTheWindowAreClipped) {
  ObstacleLayer l = make_layer();
  // From near the window's edge, a 6 m clearing ray mostly outside: no crash, cells inside cleared.
  l.update(make_scan(1, 0.0, 0.0, kInf), Pose2{7.55, 0.05, 0.0});
  EXPECT_EQ(l.grid().at(79, 0), cost::kFree);
  // From outside the window, looking in.
  l.update(make_scan(1, kPi, 0.0, 4.0F), Pose2{9.05, 1.05, 0.0});
  EXPECT_EQ(l.grid().at(79, 10), cost::kFree);
  EXPECT_EQ(l.grid().at(50, 10), cost::kLethal);
}

TEST(ObstacleLayerTest, UpdateDoesNotAllocate) {
  ObstacleLayer l = make_layer();
  hal::LaserScan s = make_scan(541, -135 * kDeg, 0.5 * kDeg, 3.0F);
  for (int i = 0; i < 541; i += 7) s.ranges_m[std::size_t(i)] = kInf;
  l.update(s, kOrigin);  // warm up
  alloc::begin_window();
  for (int i = 0; i < 5; ++i) l.update(s, Pose2{0.1 * i, 0.0, 0.1 * i});
  l.recenter(0.5, 0.5);
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
  EXPECT_GT(alloc::count_total(), 0U);
}

TEST(ObstacleLayerTest, ValidateNamesTheKey) {
  ObstacleLayerConfig cfg;
  cfg.clear_scans = 0;
  EXPECT_NE(std::string(cfg.validate().message()).find("clear_scans"), std::string::npos);
  cfg = {};
  cfg.raytrace_min_range_m = 7.0;
  EXPECT_NE(std::string(cfg.validate().message()).find("raytrace_min_range_m"), std::string::npos);
  cfg = {};
  cfg.obstacle_max_range_m = std::nan("");
  EXPECT_NE(std::string(cfg.validate().message()).find("obstacle_max_range_m"), std::string::npos);
}

}  // namespace
}  // namespace carril::fw
