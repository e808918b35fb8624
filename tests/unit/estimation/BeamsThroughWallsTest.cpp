// beams_through_walls: at the true pose no return crosses a wall; seen from a wrong pose many do;
// the count agrees with a brute-force test of each beam's segment against every occupied cell;
// the margins spare a return that ends just past a wall's face; unknown cells, invalid returns
// and the beams not picked do not count.
#include "firmware/estimation/BeamsThroughWalls.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "tests/unit/estimation/MclWorld.hpp"

namespace carril::fw {
namespace {

using test::mcl::kRes;

// Whether the segment (x0, y0) -> (x1, y1) meets the closed box [bx0, bx1] x [by0, by1] (slabs).
bool segment_meets_box(double x0, double y0, double x1, double y1, double bx0, double by0,
                       double bx1, double by1) {
  double t0 = 0.0, t1 = 1.0;
  const double d[2] = {x1 - x0, y1 - y0}, p[2] = {x0, y0}, lo[2] = {bx0, by0}, hi[2] = {bx1, by1};
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0.0) {
      if (p[a] < lo[a] || p[a] > hi[a]) return false;
      continue;
    }
    double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// The reference: every valid return (max_beams at least the valid count picks them all), its
// segment between the margins tested against the box of every occupied cell.
int through_by_brute_force(const OccupancyGrid& map, const hal::LaserScan& scan, const Pose2& pose,
                           double margin) {
  const Vec2 s = to_world(pose, Vec2(0.0, 0.0));
  int through = 0;
  for (int k = 0; k < int(scan.count); ++k) {
    const double r = double(scan.ranges_m[std::size_t(k)]);
    if (!std::isfinite(r) || r < double(scan.range_min_m) || r >= double(scan.range_max_m)) {
      continue;
    }
    if (r <= 2.0 * margin) continue;
    const double a = pose.yaw + double(scan.angle_min_rad) + k * double(scan.angle_increment_rad);
    const double c = std::cos(a), sn = std::sin(a);
    const double x0 = s.x() + margin * c, y0 = s.y() + margin * sn;
    const double x1 = s.x() + (r - margin) * c, y1 = s.y() + (r - margin) * sn;
    bool hit = false;
    for (int j = 0; j < map.ny() && !hit; ++j) {
      for (int i = 0; i < map.nx() && !hit; ++i) {
        if (map.at(i, j) != cost::kLethal) continue;
        const double bx = map.info().origin_x_m + i * kRes, by = map.info().origin_y_m + j * kRes;
        hit = segment_meets_box(x0, y0, x1, y1, bx, by, bx + kRes, by + kRes);
      }
    }
    through += hit ? 1 : 0;
  }
  return through;
}

// A free pose of the house at least `clear` [m] from any occupied or unknown cell.
Pose2 free_pose(const OccupancyGrid& map, MclRng& rng, double clear) {
  for (;;) {
    const Pose2 p{rng.uniform(0.2, 9.8), rng.uniform(0.2, 7.8), rng.uniform(-kPi, kPi)};
    bool ok = true;
    const int n = int(std::ceil(clear / kRes));
    int ci = 0, cj = 0;
    (void)map.cell_of(p.x, p.y, ci, cj);
    for (int j = cj - n; j <= cj + n && ok; ++j) {
      for (int i = ci - n; i <= ci + n && ok; ++i) ok = map.at(i, j) == cost::kFree;
    }
    if (ok) return p;
  }
}

TEST(BeamsThroughWalls, AtTheTruePoseNoReturnCrossesAWall) {
  const OccupancyGrid map = test::mcl::make_house();
  MclRng rng(7);
  test::mcl::ScanSpec spec;  // 1 cm noise, drop-outs, short clutter returns
  int checked = 0;
  for (int n = 0; n < 200; ++n) {
    const Pose2 p = free_pose(map, rng, 0.3);
    hal::LaserScan scan;
    test::mcl::synth_scan(map, p, {}, spec, rng, scan);
    const BeamsThroughWalls b = beams_through_walls(map, scan, p, {}, 60, 10.0, 0.05);
    EXPECT_EQ(b.through, 0) << n << ": " << p.x << ", " << p.y << ", " << p.yaw;
    EXPECT_EQ(b.checked, 60);
    checked += b.checked;
  }
  EXPECT_EQ(checked, 200 * 60);
}

TEST(BeamsThroughWalls, SeenFromAWrongPoseManyReturnsCrossTheWalls) {
  const OccupancyGrid map = test::mcl::make_house();
  MclRng rng(11);
  test::mcl::ScanSpec spec;
  int crossed = 0;
  for (int n = 0; n < 50; ++n) {
    const Pose2 truth = free_pose(map, rng, 0.3);
    hal::LaserScan scan;
    test::mcl::synth_scan(map, truth, {}, spec, rng, scan);
    // The same scan placed 1 m away, and turned half round at the true position.
    const Pose2 shifted{truth.x + std::cos(truth.yaw), truth.y + std::sin(truth.yaw), truth.yaw};
    const Pose2 turned{truth.x, truth.y, wrap_angle(truth.yaw + kPi)};
    const double f1 = beams_through_walls(map, scan, shifted, {}, 60, 10.0, 0.3).fraction();
    const double f2 = beams_through_walls(map, scan, turned, {}, 60, 10.0, 0.3).fraction();
    crossed += (f1 > 0.1 ? 1 : 0) + (f2 > 0.1 ? 1 : 0);
  }
  // A few wrong poses look into a room from a spot where that room looks the same.
  EXPECT_GE(crossed, 90) << "of 100 wrong poses";
}

TEST(BeamsThroughWalls, TheCountAgreesWithABruteForceTestOfEverySegment) {
  const OccupancyGrid map = test::mcl::make_house();
  MclRng rng(3);
  test::mcl::ScanSpec spec;
  spec.beams = 90;
  int total = 0;
  for (int n = 0; n < 60; ++n) {
    const Pose2 truth = free_pose(map, rng, 0.3);
    hal::LaserScan scan;
    test::mcl::synth_scan(map, truth, {}, spec, rng, scan);
    // Half the poses wrong by up to a metre and half a radian.
    const Pose2 seen =
        n % 2 == 0 ? truth
                   : Pose2{truth.x + rng.uniform(-1.0, 1.0), truth.y + rng.uniform(-1.0, 1.0),
                           wrap_angle(truth.yaw + rng.uniform(-0.5, 0.5))};
    for (const double margin : {0.0, 0.1, 0.3}) {
      const BeamsThroughWalls b = beams_through_walls(map, scan, seen, {}, 360, 10.0, margin);
      const int expected = through_by_brute_force(map, scan, seen, margin);
      EXPECT_EQ(b.through, expected) << n << " margin " << margin;
      total += expected;
    }
  }
  EXPECT_GT(total, 500);  // the wrong poses crossed walls: the comparison was not all zeros
}

// A 4 x 2 m map, free but for a 0.1 m wall across it at x in [2.0, 2.1] and an unknown block at
// x in [1.0, 1.2], y in [1.2, 2.0]; one-beam scans from (0.5, y) along +x.
struct OneWall {
  OccupancyGrid map{80 * 40};
  OneWall() {
    std::vector<std::uint8_t> c(80 * 40, cost::kFree);
    for (int j = 0; j < 40; ++j) {
      for (int i = 0; i < 80; ++i) {
        if (i >= 40 && i < 42) c[std::size_t(j * 80 + i)] = cost::kLethal;
        if (i >= 20 && i < 24 && j >= 24) c[std::size_t(j * 80 + i)] = cost::kUnknown;
      }
    }
    EXPECT_TRUE(map.assign({80, 40, kRes, 0.0, 0.0}, c.data()).is_ok());
  }
  static hal::LaserScan one_beam(float r) {
    hal::LaserScan s;
    s.count = 1;
    s.range_min_m = 0.05F;
    s.range_max_m = 8.0F;
    s.ranges_m[0] = r;
    return s;
  }
};

TEST(BeamsThroughWalls, TheMarginsSpareAReturnThatEndsJustPastAWallsFace) {
  OneWall w;
  const Pose2 p{0.5, 0.5, 0.0};
  // The wall's face is 1.5 m away; a return of 1.75 m ends 0.25 m into and past it.
  const hal::LaserScan s = OneWall::one_beam(1.75F);
  EXPECT_EQ(beams_through_walls(w.map, s, p, {}, 60, 8.0, 0.3).through, 0);
  EXPECT_EQ(beams_through_walls(w.map, s, p, {}, 60, 8.0, 0.2).through, 1);
  EXPECT_EQ(beams_through_walls(w.map, s, p, {}, 60, 8.0, 0.0).through, 1);
  // The return on the face: its own end cell is the wall's (margin 0 counts it), any margin
  // spares it.
  const hal::LaserScan face = OneWall::one_beam(1.5F);
  EXPECT_EQ(beams_through_walls(w.map, face, p, {}, 60, 8.0, 0.0).through, 1);
  EXPECT_EQ(beams_through_walls(w.map, face, p, {}, 60, 8.0, 0.01).through, 0);
  // The scanner's mount counts: 0.3 m forward, the same return ends 0.3 m farther on.
  EXPECT_EQ(beams_through_walls(w.map, face, p, {0.3, 0.0, 0.0}, 60, 8.0, 0.1).through, 1);
  // Past the far wall of the map: through the wall, then off the map.
  const hal::LaserScan far = OneWall::one_beam(7.9F);
  EXPECT_EQ(beams_through_walls(w.map, far, p, {}, 60, 8.0, 0.3).through, 1);
}

TEST(BeamsThroughWalls, UnknownCellsInvalidReturnsAndBeamsNotPickedDoNotCount) {
  OneWall w;
  // Through the unknown block only (it ends before the wall): not through.
  EXPECT_EQ(beams_through_walls(w.map, OneWall::one_beam(1.2F), {0.5, 1.5, 0.0}, {}, 60, 8.0, 0.1)
                .through,
            0);
  // Returns that are not valid are not checked at all.
  for (const float r : {std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::infinity(), 0.01F, 8.0F, 9.0F}) {
    const BeamsThroughWalls b =
        beams_through_walls(w.map, OneWall::one_beam(r), {0.5, 0.5, 0.0}, {}, 60, 8.0, 0.1);
    EXPECT_EQ(b.checked, 0) << r;
    EXPECT_EQ(b.fraction(), 0.0) << r;
  }
  // max_range_m below the scanner's: a return beyond it is not checked either.
  EXPECT_EQ(beams_through_walls(w.map, OneWall::one_beam(3.0F), {0.5, 0.5, 0.0}, {}, 60, 2.5, 0.1)
                .checked,
            0);
  // Ten returns, five of them past the wall: max_beams 2 picks the valid returns of rank 2
  // and 7 (evenly spaced), one short and one long.
  hal::LaserScan s;
  s.count = 10;
  s.range_min_m = 0.05F;
  s.range_max_m = 8.0F;
  s.angle_increment_rad = 0.0F;  // all along +x: only the ranges differ
  for (int k = 0; k < 10; ++k) s.ranges_m[std::size_t(k)] = k < 5 ? 1.0F : 3.0F;
  const BeamsThroughWalls two = beams_through_walls(w.map, s, {0.5, 0.5, 0.0}, {}, 2, 8.0, 0.1);
  EXPECT_EQ(two.checked, 2);
  EXPECT_EQ(two.through, 1);
  EXPECT_DOUBLE_EQ(two.fraction(), 0.5);
  const BeamsThroughWalls all = beams_through_walls(w.map, s, {0.5, 0.5, 0.0}, {}, 60, 8.0, 0.1);
  EXPECT_EQ(all.checked, 10);
  EXPECT_EQ(all.through, 5);
}

}  // namespace
}  // namespace carril::fw
