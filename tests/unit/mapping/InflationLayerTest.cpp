#include "firmware/mapping/InflationLayer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

constexpr double kRes = 0.05;

// Nav2's formula at a distance d [m] from the nearest lethal cell (the reference).
int formula(const InflationConfig& c, double d) {
  if (d == 0.0) return cost::kLethal;
  if (d <= c.inscribed_radius_m + 1e-9) return cost::kInscribed;
  if (d > c.inflation_radius_m + 1e-9) return 0;
  return int(252.0 * std::exp(-c.cost_scaling_factor * (d - c.inscribed_radius_m)));
}

InflationConfig default_config() {
  InflationConfig c;
  c.inscribed_radius_m = 0.22;
  c.inflation_radius_m = 0.55;
  c.cost_scaling_factor = 10.0;
  return c;
}

RollingGrid<std::uint8_t> make_grid(int n, std::uint8_t fill, int ox = 0, int oy = 0) {
  RollingGrid<std::uint8_t> g;
  EXPECT_TRUE(g.init(n, n, kRes, fill));
  g.move_origin(ox, oy);
  return g;
}

// Brute force: the exact nearest lethal cell over the whole window, then the combination rule.
std::vector<int> brute_force(const RollingGrid<std::uint8_t>& src, const InflationConfig& c) {
  std::vector<int> lethal;
  for (int ly = 0; ly < src.ny(); ++ly)
    for (int lx = 0; lx < src.nx(); ++lx)
      if (src.local(lx, ly) == cost::kLethal) lethal.push_back(ly * src.nx() + lx);
  std::vector<int> out(std::size_t(src.nx() * src.ny()));
  for (int ly = 0; ly < src.ny(); ++ly) {
    for (int lx = 0; lx < src.nx(); ++lx) {
      double best = HUGE_VAL;
      for (int k : lethal) {
        const int dx = k % src.nx() - lx, dy = k / src.nx() - ly;
        best = std::min(best, std::sqrt(double(dx * dx + dy * dy)) * kRes);
      }
      const int inf = std::isfinite(best) ? formula(c, best) : 0;
      const int old = src.local(lx, ly);
      out[std::size_t(ly * src.nx() + lx)] =
          old == cost::kUnknown ? (inf > 0 ? inf : old) : std::max(old, inf);
    }
  }
  return out;
}

TEST(InflationLayerTest, CostsAroundOneLethalCellFollowTheFormula) {
  const InflationConfig c = default_config();
  InflationLayer inf;
  ASSERT_TRUE(inf.init(c, 40, 40, kRes));
  EXPECT_EQ(inf.radius_cells(), 11);
  auto g = make_grid(40, cost::kFree);
  g.local(20, 20) = cost::kLethal;
  g.local(2, 2) = cost::kUnknown;    // far from the lethal cell: stays unknown
  g.local(22, 20) = cost::kUnknown;  // inside the inscribed circle: becomes 253
  inf.apply(g, g);
  EXPECT_EQ(g.local(20, 20), cost::kLethal);
  EXPECT_EQ(g.local(22, 20), cost::kInscribed);
  EXPECT_EQ(g.local(2, 2), cost::kUnknown);
  for (int dy = -14; dy <= 14; ++dy) {
    for (int dx = -14; dx <= 14; ++dx) {
      if (dx == 2 && dy == 0) continue;
      const double d = std::sqrt(double(dx * dx + dy * dy)) * kRes;
      EXPECT_EQ(int(g.local(20 + dx, 20 + dy)), formula(c, d)) << dx << "," << dy;
    }
  }
  // The inscribed ring: 0.22 m is 4.4 cells, so (4, 0) and (3, 3) are in, (5, 0) is out.
  EXPECT_EQ(g.local(24, 20), cost::kInscribed);
  EXPECT_EQ(g.local(23, 23), cost::kInscribed);
  EXPECT_LT(g.local(25, 20), cost::kInscribed);
  EXPECT_EQ(g.local(31, 20), formula(c, 0.55));  // exactly on the inflation radius
  EXPECT_GT(g.local(31, 20), 0);
  EXPECT_EQ(g.local(32, 20), cost::kFree);
}

TEST(InflationLayerTest, CostsFromAWallFollowTheFormula) {
  const InflationConfig c = default_config();
  InflationLayer inf;
  ASSERT_TRUE(inf.init(c, 60, 60, kRes));
  auto g = make_grid(60, cost::kFree, -30, 7);  // an offset window: storage wraps
  for (int ly = 0; ly < 60; ++ly) g.local(25, ly) = cost::kLethal;
  inf.apply(g, g);
  for (int k = 0; k < 20; ++k) {
    for (int ly : {0, 17, 59}) {
      EXPECT_EQ(int(g.local(25 + k, ly)), formula(c, k * kRes)) << k;
      EXPECT_EQ(int(g.local(25 - k, ly)), formula(c, k * kRes)) << k;
    }
  }
}

// Every cell equals a brute-force reference exactly (distances are exact): random lethal,
// unknown and graded cells, a window whose storage wraps, in place and into another grid. Dense
// lethal cells (1.5 %) and sparse ones (0.1 %: most rows have a few columns near one, the case
// where only part of a row is computed).
TEST(InflationLayerTest, MatchesBruteForceOnRandomGrids) {
  std::mt19937 rng(7);
  for (int run = 0; run < 8; ++run) {
    const int trial = run % 4, lethal_per_mille = run < 4 ? 15 : 1;
    InflationConfig c = default_config();
    c.inscribed_radius_m = 0.1 + 0.05 * trial;
    c.inflation_radius_m = 0.3 + 0.12 * trial;
    c.cost_scaling_factor = 3.0 + 4.0 * trial;
    const int n = 50 + 7 * trial + 3 * (run / 4);
    InflationLayer inf;
    ASSERT_TRUE(inf.init(c, n, n, kRes));
    auto src = make_grid(n, cost::kFree, -13 * trial, 5 * trial - 9);
    std::uniform_int_distribution<int> pick(0, 999);
    for (int ly = 0; ly < n; ++ly) {
      for (int lx = 0; lx < n; ++lx) {
        const int p = pick(rng);
        src.local(lx, ly) = p < lethal_per_mille ? cost::kLethal
                            : p < 200            ? cost::kUnknown
                            : p < 260            ? std::uint8_t(p - 200)
                                                 : cost::kFree;
      }
    }
    const std::vector<int> want = brute_force(src, c);
    auto dst = make_grid(n, 77, src.origin_cx(), src.origin_cy());
    inf.apply(src, dst);
    inf.apply(src, src);
    int mismatches = 0;
    for (int ly = 0; ly < n; ++ly) {
      for (int lx = 0; lx < n; ++lx) {
        const int w = want[std::size_t(ly * n + lx)];
        if (dst.local(lx, ly) != w || src.local(lx, ly) != w) ++mismatches;
      }
    }
    EXPECT_EQ(mismatches, 0) << "run " << run;
  }
}

// The largest radius init() takes (kMaxRadiusCells): the capped vertical distances reach
// kMaxRadiusCells + 1, the top of their byte arithmetic. A few lethal cells in a grid wider than
// the radius, unknown cells round them, a wrapped window: every cell equals the brute force.
TEST(InflationLayerTest, MatchesBruteForceAtTheLargestRadius) {
  InflationConfig c = default_config();
  c.inflation_radius_m = InflationLayer::kMaxRadiusCells * kRes;
  c.cost_scaling_factor = 0.5;  // costs still above 0 far out, so far cells are checked too
  const int n = 2 * InflationLayer::kMaxRadiusCells + 20;
  InflationLayer inf;
  ASSERT_TRUE(inf.init(c, n, n, kRes));
  auto src = make_grid(n, cost::kFree, -37, 81);
  for (int ly = 0; ly < n; ly += 9) src.local((ly * 7) % n, ly) = cost::kUnknown;
  src.local(3, 5) = cost::kLethal;
  src.local(n - 2, n / 2) = cost::kLethal;
  src.local(n / 2, n - 1) = cost::kLethal;
  const std::vector<int> want = brute_force(src, c);
  inf.apply(src, src);
  int mismatches = 0, costed_far = 0;
  for (int ly = 0; ly < n; ++ly) {
    for (int lx = 0; lx < n; ++lx) {
      const int w = want[std::size_t(ly * n + lx)];
      if (src.local(lx, ly) != w) ++mismatches;
      if (w > 0 && w < 50) ++costed_far;
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(costed_far, 1000);  // the far, low costs are there to be compared
}

// Pairs of lethal cells 1 to 4R + 4 columns apart, each pair in its own band of rows: the rows
// hold two clusters of costed columns whose widenings overlap, touch, or lie apart (each cluster
// is inflated on its own), on a window whose storage wraps inside the pairs.
TEST(InflationLayerTest, ClustersOfCostedColumnsAreEachInflated) {
  const InflationConfig c = default_config();  // R = 11 cells
  const int R = 11, n = 120;
  for (int ox : {0, -37, 61}) {
    InflationLayer inf;
    ASSERT_TRUE(inf.init(c, n, n, kRes));
    auto src = make_grid(n, cost::kFree, ox, 23);
    int pairs = 0;
    for (int sep = 1, band = 0; sep <= 4 * R + 4; ++sep, band = (band + 1) % 4) {
      const int ly = 5 + band * 30 + (sep % 3);
      const int lx = (sep * 7) % (n - sep - 2);
      src.local(lx, ly) = cost::kLethal;
      src.local(lx + sep, ly + (sep % 2)) = cost::kLethal;
      ++pairs;
      if (band == 3) {  // a band at a time: compare, then start again
        const std::vector<int> want = brute_force(src, c);
        auto dst = make_grid(n, 77, src.origin_cx(), src.origin_cy());
        inf.apply(src, dst);
        int mismatches = 0;
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x)
            if (dst.local(x, y) != want[std::size_t(y * n + x)]) ++mismatches;
        EXPECT_EQ(mismatches, 0) << "origin " << ox << " up to separation " << sep;
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) src.local(x, y) = cost::kFree;
      }
    }
    EXPECT_EQ(pairs, 4 * R + 4);
  }
}

TEST(InflationLayerTest, NoLethalCellLeavesTheGridAsItWas) {
  InflationLayer inf;
  ASSERT_TRUE(inf.init(default_config(), 30, 30, kRes));
  auto g = make_grid(30, cost::kUnknown);
  g.local(3, 4) = cost::kFree;
  g.local(5, 6) = 120;
  auto out = make_grid(30, 9);
  inf.apply(g, out);
  for (int ly = 0; ly < 30; ++ly)
    for (int lx = 0; lx < 30; ++lx) ASSERT_EQ(out.local(lx, ly), g.local(lx, ly));
}

TEST(InflationLayerTest, ApplyDoesNotAllocate) {
  InflationLayer inf;
  ASSERT_TRUE(inf.init(default_config(), 100, 100, kRes));
  auto g = make_grid(100, cost::kFree);
  for (int i = 0; i < 100; i += 3) g.local(i, (i * 7) % 100) = cost::kLethal;
  alloc::begin_window();
  inf.apply(g, g);
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
  EXPECT_GT(alloc::count_total(), 0U);
}

TEST(InflationLayerTest, ValidateAndInitRejectBadRadii) {
  InflationConfig c = default_config();
  c.inflation_radius_m = 0.1;  // below the inscribed radius
  EXPECT_NE(std::string(c.validate().message()).find("inflation_radius_m"), std::string::npos);
  c = default_config();
  c.cost_scaling_factor = -1.0;
  EXPECT_NE(std::string(c.validate().message()).find("cost_scaling_factor"), std::string::npos);
  c = default_config();
  c.inflation_radius_m = 9.0;  // 180 cells at 5 cm
  InflationLayer inf;
  EXPECT_FALSE(inf.init(c, 10, 10, kRes));
}

}  // namespace
}  // namespace carril::fw
