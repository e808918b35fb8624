// The Localisation component: without a map the pose is the odometry, bit for bit; on a map it
// starts where it is told, converges onto the true pose from the scans (held unlocalised until
// then) and allocates nothing in its ticks.
#include "firmware/app/Localisation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "tests/support/CountingAllocator.hpp"

namespace carril::fw {
namespace {

// A 6 x 4 m room at 0.05 m, walls 0.1 m, a 1 x 0.5 m block off centre (no symmetry).
std::vector<std::uint8_t> room(MapInfo& info) {
  info = {120, 80, 0.05, -3.0, -2.0};
  std::vector<std::uint8_t> c(120 * 80, cost::kFree);
  for (int j = 0; j < 80; ++j) {
    for (int i = 0; i < 120; ++i) {
      const bool wall = i < 2 || j < 2 || i >= 118 || j >= 78;
      const bool block = i >= 80 && i < 100 && j >= 50 && j < 60;
      if (wall || block) c[std::size_t(j) * 120 + std::size_t(i)] = cost::kLethal;
    }
  }
  return c;
}

// A 360-beam, 360 deg scan from the pose, by a fine march through the grid.
hal::LaserScan scan_from(const OccupancyGrid& map, const Pose2& p, std::uint32_t seq) {
  hal::LaserScan s;
  s.seq = seq;
  s.count = 360;
  s.angle_min_rad = float(-kPi);
  s.angle_increment_rad = float(2.0 * kPi / 360.0);
  s.range_min_m = 0.05F;
  s.range_max_m = 8.0F;
  for (int k = 0; k < 360; ++k) {
    const double a = p.yaw + double(s.angle_min_rad) + k * double(s.angle_increment_rad);
    double r = 0.0;
    for (; r < 8.0; r += 0.005) {
      int i = 0, j = 0;
      if (!map.cell_of(p.x + r * std::cos(a), p.y + r * std::sin(a), i, j) ||
          map.at(i, j) == cost::kLethal) {
        break;
      }
    }
    s.ranges_m[std::size_t(k)] = float(r);
  }
  return s;
}

struct Rig {
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom, pose;
  hal::LaserScan scan;
  void tick(Localisation& l, std::int64_t t_ns, const hal::LaserScan* s) {
    SensorFrame& f = frame.edit();
    f.now_ns = t_ns;
    f.scan = s;
    frame.publish(t_ns);
    odom.publish(odom.get(), t_ns);
    l.run();
  }
};

TEST(Localisation, WithoutAMapThePoseIsTheOdometryBitForBit) {
  Rig r;
  LocalisationConfig cfg;
  Localisation l(cfg, nullptr, r.frame, r.odom, r.pose);
  r.odom.edit().pose = {1.0 / 3.0, -2.0 / 7.0, 3.1};
  r.tick(l, 0, nullptr);
  EXPECT_EQ(r.pose.get().pose.x, 1.0 / 3.0);
  EXPECT_EQ(r.pose.get().pose.y, -2.0 / 7.0);
  EXPECT_EQ(r.pose.get().pose.yaw, 3.1);
  EXPECT_TRUE(r.pose.get().localised);
}

TEST(Localisation, OnAMapItConvergesOntoTheTruePoseAndOnlyThenIsLocalised) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = room(info);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  const Pose2 truth{0.7, -0.4, 0.3};
  Rig r;
  LocalisationConfig cfg;
  cfg.enabled = true;
  cfg.initial_pose = {1.2, -0.1, 0.3 + 0.35};  // 0.58 m and 20 deg off
  cfg.initial_sigma_xy_m = 0.6;
  cfg.initial_sigma_yaw_rad = 0.4;
  cfg.mcl.max_particles = 2000;
  cfg.mcl.sigma_hit_m = 0.1;
  cfg.mcl.laser_max_range_m = 8.0;
  ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  Localisation l(cfg, &map, r.frame, r.odom, r.pose);
  ASSERT_NE(l.filter(), nullptr);
  ASSERT_TRUE(l.filter()->status().is_ok()) << l.filter()->status().message();
  // The robot stands still at the true pose; its odometry starts at zero.
  std::vector<hal::LaserScan> scans;
  for (std::uint32_t k = 1; k <= 40; ++k) scans.push_back(scan_from(map, truth, k));
  r.tick(l, 0, nullptr);
  EXPECT_FALSE(r.pose.get().localised);  // no scan weighed yet
  test::alloc::begin_window();
  std::int64_t t = 0;
  for (const hal::LaserScan& s : scans) {
    for (int k = 0; k < 5; ++k) r.tick(l, t += 10'000'000, &s);  // 20 Hz scans, 100 Hz ticks
  }
  test::alloc::end_window();
  EXPECT_EQ(test::alloc::count_in_windows(), 0U);
  const Pose2& p = r.pose.get().pose;
  EXPECT_TRUE(r.pose.get().localised);
  EXPECT_LT(std::hypot(p.x - truth.x, p.y - truth.y), 0.1) << p.x << ", " << p.y;
  EXPECT_LT(std::abs(wrap_angle(p.yaw - truth.yaw)), 0.05) << p.yaw;
  EXPECT_GE(l.telemetry().updates, 1U);
  EXPECT_EQ(l.telemetry().lost, 0U);
}

}  // namespace
}  // namespace carril::fw
