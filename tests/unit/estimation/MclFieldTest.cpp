// Monte Carlo localisation, the sensor model and the random numbers: the likelihood field's
// distances against brute force, its table against the formula, ray-cast endpoints at the true
// pose on obstacles; xoshiro256** against an independent implementation, the portable log and
// the Gaussian's moments.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "firmware/estimation/LikelihoodField.hpp"
#include "firmware/estimation/MclMath.hpp"
#include "firmware/estimation/MclRandom.hpp"
#include "tests/unit/estimation/MclWorld.hpp"

namespace carril::fw {
namespace {

using test::mcl::cast_ray;
using test::mcl::make_house;

OccupancyGrid make_grid(int nx, int ny, double res, const std::vector<std::uint8_t>& cells,
                        double ox = 0.0, double oy = 0.0) {
  OccupancyGrid g(cells.size());
  MapInfo info;
  info.nx = nx;
  info.ny = ny;
  info.resolution_m = res;
  info.origin_x_m = ox;
  info.origin_y_m = oy;
  EXPECT_TRUE(g.assign(info, cells.data()).is_ok());
  return g;
}

// Nearest occupied cell centre by trying them all.
double brute_distance(const OccupancyGrid& g, int i, int j, double max_dist) {
  long best = -1;
  for (int b = 0; b < g.ny(); ++b) {
    for (int a = 0; a < g.nx(); ++a) {
      if (g.at(a, b) != cost::kLethal) continue;
      const long d2 = long(a - i) * (a - i) + long(b - j) * (b - j);
      if (best < 0 || d2 < best) best = d2;
    }
  }
  if (best < 0) return max_dist;
  return std::min(std::sqrt(double(best)) * g.resolution(), max_dist);
}

TEST(MclLikelihoodField, DistancesMatchBruteForceOnRandomMaps) {
  MclRng rng(7);
  struct Case {
    int nx, ny;
    double density, max_dist;
  };
  // Sparse, dense, a single obstacle, none, and a max_dist beyond the map.
  const Case cases[] = {{41, 29, 0.01, 1.0}, {33, 47, 0.2, 0.6},   {64, 9, 0.0, 2.0},
                        {25, 25, -1.0, 1.0}, {57, 38, 0.002, 9.0}, {1, 30, 0.05, 1.0}};
  for (const Case& c : cases) {
    std::vector<std::uint8_t> cells(std::size_t(c.nx * c.ny), cost::kFree);
    for (auto& v : cells) {
      const double u = rng.uniform();
      v = u < c.density ? cost::kLethal : (u < c.density + 0.1 ? cost::kUnknown : cost::kFree);
    }
    if (c.density == 0.0) cells[std::size_t(c.nx * 4 + 50)] = cost::kLethal;
    const OccupancyGrid g = make_grid(c.nx, c.ny, 0.05, cells, -1.3, 2.7);
    LikelihoodFieldConfig cfg;
    cfg.max_dist_m = c.max_dist;
    const LikelihoodField f(cfg, g);
    ASSERT_TRUE(f.ok());
    int mismatches = 0;
    for (int j = 0; j < c.ny; ++j) {
      for (int i = 0; i < c.nx; ++i) {
        const double want = brute_distance(g, i, j, c.max_dist);
        if (f.distance(i, j) != want) ++mismatches;
        EXPECT_EQ(f.distance(i, j), want)
            << "cell " << i << ", " << j << " of " << c.nx << " x " << c.ny;
        if (mismatches > 5) return;
      }
    }
  }
}

TEST(MclLikelihoodField, TableHoldsTheSensorModel) {
  const OccupancyGrid g = make_house();
  LikelihoodFieldConfig cfg;
  cfg.z_hit = 0.9;
  cfg.z_rand = 0.1;
  cfg.sigma_hit_m = 0.1;
  cfg.z_max_m = 8.0;
  cfg.max_dist_m = 1.0;
  const LikelihoodField f(cfg, g);
  ASSERT_TRUE(f.ok());
  // On an obstacle: 0.9 / (sqrt(2 pi) 0.1) + 0.1 / 8 = 3.590480 + 0.0125.
  EXPECT_NEAR(f.log_p_max(), std::log(3.5904805 + 0.0125), 1e-6);
  // At 0.1 m: the Gaussian is exp(-0.5) of its peak.
  EXPECT_NEAR(f.log_p_of_distance(0.1), std::log(3.5904805 * std::exp(-0.5) + 0.0125), 1e-6);
  // At max_dist and beyond: exp(-50) of the peak, the random term only up to 1e-22.
  EXPECT_NEAR(f.log_p_min(), std::log(0.0125), 1e-9);
  EXPECT_EQ(f.log_p_of_distance(5.0), f.log_p_min());
  // Every cell centre reads its own distance's value.
  for (int j = 0; j < g.ny(); ++j) {
    for (int i = 0; i < g.nx(); ++i) {
      const Vec2 c = g.centre(i, j);
      ASSERT_EQ(f.log_p(c.x(), c.y()), float(f.log_p_of_distance(f.distance(i, j))))
          << i << ", " << j;
    }
  }
  // Off the map, near and very far: max_dist's value.
  const float off = float(f.log_p_min());
  for (const Vec2& p : {Vec2(-0.01, 4.0), Vec2(10.01, 4.0), Vec2(5.0, -0.2), Vec2(5.0, 8.3),
                        Vec2(-1e9, 1e9), Vec2(1e12, -3.0)}) {
    EXPECT_EQ(f.log_p(p.x(), p.y()), off) << p.transpose();
  }
}

// A wall four cells thick (columns 20 to 23 of a 40 x 5 map, 0.05 m cells): to cell centres the
// whole wall reads distance 0 (an estimate may slide 0.1 m into it for free); to the surface
// the faces read half a cell on both sides and the inside is as unlikely as the outside.
TEST(MclLikelihoodField, SurfaceDistancesPenaliseEndpointsInsideAThickWall) {
  std::vector<std::uint8_t> cells(40 * 5, cost::kFree);
  for (int j = 0; j < 5; ++j)
    for (int i = 20; i < 24; ++i) cells[std::size_t(j * 40 + i)] = cost::kLethal;
  const OccupancyGrid g = make_grid(40, 5, 0.05, cells);
  LikelihoodFieldConfig cfg;
  cfg.sigma_hit_m = 0.1;
  const LikelihoodField centres(cfg, g);
  cfg.surface_distance = true;
  const LikelihoodField surface(cfg, g);
  ASSERT_TRUE(centres.ok() && surface.ok());
  const auto at = [&](const LikelihoodField& f, int i) {
    const Vec2 c = g.centre(i, 2);
    return f.log_p(c.x(), c.y());
  };
  const auto p = [&](double d) { return float(surface.log_p_of_distance(d)); };
  for (int i = 20; i < 24; ++i) EXPECT_EQ(at(centres, i), p(0.0)) << i;
  EXPECT_EQ(at(centres, 19), p(0.05));
  // Free side, 1.5 and 0.5 cells from the face; the face cells; 1.5 cells deep on both sides.
  EXPECT_EQ(at(surface, 18), p(0.075));
  EXPECT_EQ(at(surface, 19), p(0.025));
  EXPECT_EQ(at(surface, 20), p(0.025));
  EXPECT_EQ(at(surface, 21), p(0.075));
  EXPECT_EQ(at(surface, 22), p(0.075));
  EXPECT_EQ(at(surface, 23), p(0.025));
  EXPECT_EQ(at(surface, 24), p(0.025));
  // The distances the filter reports stay to cell centres.
  EXPECT_DOUBLE_EQ(surface.distance(19, 2), 0.05);
  EXPECT_DOUBLE_EQ(surface.distance(21, 2), 0.0);
}

TEST(MclLikelihoodField, UnknownCellsMeasureTheirDistanceLikeFreeOnes) {
  const OccupancyGrid g = make_house();
  const LikelihoodField f(LikelihoodFieldConfig{}, g);
  // The closet's inside is unknown; its centre cell is 0.15 m or so from its walls.
  int i = 0, j = 0;
  ASSERT_TRUE(g.cell_of(6.52, 7.52, i, j));
  ASSERT_EQ(g.at(i, j), cost::kUnknown);
  EXPECT_GT(f.distance(i, j), 0.1);
  EXPECT_LT(f.distance(i, j), 0.5);
}

// At the true pose, the endpoint of every beam of an exact ray cast lies in an occupied cell:
// the field says distance 0 there and gives its largest value.
TEST(MclLikelihoodField, RayCastEndpointsAtTheTruePoseLieOnObstacles) {
  const OccupancyGrid g = make_house();
  const LikelihoodField f(LikelihoodFieldConfig{}, g);
  MclRng rng(3);
  int hits = 0;
  for (int n = 0; n < 50; ++n) {
    double x = 0.0, y = 0.0;
    int i = 0, j = 0;
    do {
      x = rng.uniform(0.0, 10.0);
      y = rng.uniform(0.0, 8.0);
    } while (!g.cell_of(x, y, i, j) || g.at(i, j) != cost::kFree);
    for (int k = 0; k < 360; ++k) {
      const double a = rng.uniform(-kPi, kPi);
      const double r = cast_ray(g, x, y, a, 12.0);
      if (!std::isfinite(r)) continue;
      // 0.1 mm into the cell: the table's float grid coordinates resolve about 1 um.
      const double ex = x + (r + 1e-4) * std::cos(a), ey = y + (r + 1e-4) * std::sin(a);
      ASSERT_EQ(f.distance_at(ex, ey), 0.0) << "from " << x << ", " << y << " at " << a;
      ASSERT_EQ(f.log_p(ex, ey), float(f.log_p_max()));
      ++hits;
    }
  }
  EXPECT_GT(hits, 50 * 300);
}

TEST(MclRandom, MatchesAnIndependentXoshiroImplementation) {
  // Python's reimplementation of splitmix64 seeding and xoshiro256** (the report has it).
  MclRng r(1);
  EXPECT_EQ(r.next(), 0xb3f2af6d0fc710c5ULL);
  EXPECT_EQ(r.next(), 0x853b559647364ceaULL);
  EXPECT_EQ(r.next(), 0x92f89756082a4514ULL);
  EXPECT_EQ(r.next(), 0x642e1c7bc266a3a7ULL);
  MclRng z(0);
  EXPECT_EQ(z.next(), 0x99ec5f36cb75f2b4ULL);
  EXPECT_EQ(z.next(), 0xbf6e1f784956452aULL);
}

// The Gaussian stream and fast_sincos give these bits on x86_64 and aarch64 alike (FNV-style
// hashes of 100000 values each, computed on x86_64; built without FMA contraction).
TEST(MclRandom, GaussiansAndSincosAreTheSameBitsEverywhere) {
  MclRng r(2024);
  std::uint64_t h = 0;
  for (int i = 0; i < 100000; ++i) {
    h = h * 1099511628211ULL ^ std::bit_cast<std::uint64_t>(r.gaussian());
  }
  EXPECT_EQ(h, 0x5e9d25fee352d9caULL);
  MclRng q(7);
  std::uint64_t h2 = 0;
  for (int i = 0; i < 100000; ++i) {
    double s = 0.0, c = 0.0;
    fast_sincos(q.uniform(-10, 10), s, c);
    h2 = h2 * 1099511628211ULL ^ std::bit_cast<std::uint64_t>(s) ^
         (std::bit_cast<std::uint64_t>(c) << 1);
  }
  EXPECT_EQ(h2, 0x855900c92a788678ULL);
}

TEST(MclRandom, PortableLogIsWithinFourUlpOfLibm) {
  MclRng r(11);
  for (int n = 0; n < 200000; ++n) {
    const double x = std::ldexp(0.5 + r.uniform(), int(r.below(120)) - 100);
    const double want = std::log(x), got = portable_log(x);
    ASSERT_LE(std::abs(got - want), 4.0 * std::abs(std::nextafter(want, 0.0) - want) + 1e-300) << x;
  }
  EXPECT_EQ(portable_log(1.0), 0.0);
}

TEST(MclRandom, FastSincosIsWithinItsBound) {
  MclRng r(13);
  double worst = 0.0;
  for (int n = 0; n < 200000; ++n) {
    // Mostly yaws, some angles far out (the reduction must hold there too).
    const double a = n % 10 == 0 ? r.uniform(-1e5, 1e5) : r.uniform(-7.0, 7.0);
    double s = 0.0, c = 0.0;
    fast_sincos(a, s, c);
    worst = std::max({worst, std::abs(s - std::sin(a)), std::abs(c - std::cos(a))});
  }
  EXPECT_LT(worst, 2e-10);
  double s = 0.0, c = 0.0;
  fast_sincos(0.0, s, c);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(c, 1.0);
  fast_sincos(-kPi / 2, s, c);
  EXPECT_NEAR(s, -1.0, 1e-15);
  EXPECT_NEAR(c, 0.0, 1e-15);
}

TEST(MclRandom, UniformIntegersAndGaussiansHaveTheirMoments) {
  MclRng r(5);
  constexpr int kN = 1000000;
  double s = 0.0, s2 = 0.0, s3 = 0.0, s4 = 0.0;
  int counts[7] = {};
  for (int n = 0; n < kN; ++n) {
    const double g = r.gaussian();
    s += g;
    s2 += g * g;
    s3 += g * g * g;
    s4 += g * g * g * g;
    ++counts[r.below(7)];
  }
  EXPECT_NEAR(s / kN, 0.0, 0.005);
  EXPECT_NEAR(s2 / kN, 1.0, 0.005);
  EXPECT_NEAR(s3 / kN, 0.0, 0.015);
  EXPECT_NEAR(s4 / kN, 3.0, 0.03);
  for (int c : counts) EXPECT_NEAR(c, kN / 7.0, 5.0 * std::sqrt(kN / 7.0));
}

}  // namespace
}  // namespace carril::fw
