// Boustrophedon decomposition, lanes, tour and routes on hand-made and random masks, and the
// coverage area (centre cells, coverable cells, anchors) it is fed from a static map.
#include "firmware/planning/Boustrophedon.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/CoverageGrid.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "firmware/planning/CoverageArea.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

constexpr double kRes = 0.05;

struct Mask {
  int nx, ny;
  std::vector<std::uint8_t> m;
  Mask(int w, int h, std::uint8_t fill = 1) : nx(w), ny(h), m(std::size_t(w * h), fill) {}
  std::uint8_t& at(int x, int y) { return m[std::size_t(y * nx + x)]; }
  std::uint8_t at(int x, int y) const { return m[std::size_t(y * nx + x)]; }
  void fill(int x0, int y0, int x1, int y1, std::uint8_t v) {
    for (int y = std::max(0, y0); y <= std::min(ny - 1, y1); ++y)
      for (int x = std::max(0, x0); x <= std::min(nx - 1, x1); ++x) at(x, y) = v;
  }
};

BoustrophedonConfig config(double turn_radius = 0.0) {
  BoustrophedonConfig c;
  c.lane_spacing_m = 0.45;
  c.turn_radius_m = turn_radius;
  return c;
}

Status decompose(Boustrophedon& b, const Mask& m, const BoustrophedonConfig& cfg = config()) {
  return b.decompose(m.m.data(), m.nx, m.ny, kRes, 0.0, 0.0, cfg);
}

// Every free cell belongs to exactly one decomposition cell, every blocked cell to none; each
// cell is one interval per column over its columns (and nothing outside them), its area the
// count of its cells, and the areas add up to the free cells.
void expect_partition(const Boustrophedon& b, const Mask& m) {
  std::size_t free_cells = 0;
  std::vector<std::size_t> counted(b.cell_count(), 0);
  for (int y = 0; y < m.ny; ++y) {
    for (int x = 0; x < m.nx; ++x) {
      const std::uint16_t l = b.label(x, y);
      if (m.at(x, y) == 0) {
        ASSERT_EQ(l, Boustrophedon::kNoCell) << x << "," << y;
        continue;
      }
      ++free_cells;
      ASSERT_LT(l, b.cell_count()) << x << "," << y;
      ++counted[l];
    }
  }
  std::size_t total = 0;
  for (std::size_t k = 0; k < b.cell_count(); ++k) {
    const CoverCell& c = b.cell(k);
    EXPECT_EQ(counted[k], c.area) << "cell " << k;
    total += c.area;
    for (int x = 0; x < m.nx; ++x) {
      int runs = 0;
      for (int y = 0; y < m.ny; ++y) {
        if (b.label(x, y) == k && (y == 0 || b.label(x, y - 1) != k)) ++runs;
      }
      const bool inside = x >= c.x0 && x <= c.x1;
      ASSERT_EQ(runs, inside ? 1 : 0) << "cell " << k << " column " << x;
    }
  }
  EXPECT_EQ(total, free_cells);
}

Mask random_mask(std::uint32_t seed, int nx = 60, int ny = 50) {
  std::mt19937 rng(seed);
  Mask m(nx, ny);
  std::uniform_int_distribution<int> px(0, nx - 1), py(0, ny - 1), size(1, 12);
  const int blocks = 4 + int(seed % 10);
  for (int k = 0; k < blocks; ++k) {
    const int x = px(rng), y = py(rng);
    m.fill(x, y, x + size(rng), y + size(rng), 0);
  }
  for (int k = 0; k < 30; ++k) m.at(px(rng), py(rng)) = 0;  // specks
  return m;
}

// Sweeps the routes of `visits` with a tool of the given width (the robot turning on the spot
// at each waypoint) over `grid`, whose mask says which cells count.
void sweep_routes(const Boustrophedon& b, const std::vector<CellVisit>& visits, double tool,
                  CoverageGrid& g) {
  StaticVector<Vec2, 4096> route;
  for (const CellVisit& v : visits) {
    EXPECT_TRUE(b.route(v, route));
    Pose2 at{route[0].x(), route[0].y(), 0.0};
    for (std::size_t i = 1; i < route.size(); ++i) {
      const Vec2 d = route[i] - route[i - 1];
      const double len = d.norm();
      if (len < 1e-9) continue;
      const double yaw = std::atan2(d.y(), d.x());
      const int steps = int(std::ceil(len / (0.5 * kRes)));
      for (int s = 1; s <= steps; ++s) {
        const Vec2 p = route[i - 1] + d * (double(s) / steps);
        const Pose2 next{p.x(), p.y(), yaw};
        g.sweep(at, next, tool);
        at = next;
      }
    }
  }
}

// The fraction of the cells of `cell` (kNoCell: of every free cell) that the routes of
// `visits` pass over with a tool of the given width.
double swept_fraction(const Boustrophedon& b, const Mask& m, const std::vector<CellVisit>& visits,
                      std::uint16_t cell, double tool) {
  CoverageGrid g;
  MapInfo info;
  info.nx = m.nx;
  info.ny = m.ny;
  info.resolution_m = kRes;
  EXPECT_TRUE(g.init(info).is_ok());
  std::vector<std::uint8_t> mask(m.m.size(), 0);
  for (int y = 0; y < m.ny; ++y) {
    for (int x = 0; x < m.nx; ++x) {
      const std::uint16_t l = b.label(x, y);
      mask[std::size_t(y * m.nx + x)] =
          cell == Boustrophedon::kNoCell ? l != Boustrophedon::kNoCell : l == cell;
    }
  }
  g.set_mask(mask.data());
  sweep_routes(b, visits, tool, g);
  return g.covered_fraction();
}

// The fraction of cell v.cell's cells that its own route passes over.
double route_coverage(const Boustrophedon& b, const Mask& m, const CellVisit& v, double tool) {
  return swept_fraction(b, m, {v}, v.cell, tool);
}

// The fraction of all free cells that the routes of every cell pass over.
double all_routes_coverage(const Boustrophedon& b, const Mask& m, double tool) {
  std::vector<CellVisit> all;
  for (std::size_t k = 0; k < b.cell_count(); ++k) all.push_back(CellVisit{std::uint16_t(k), 0});
  return swept_fraction(b, m, all, Boustrophedon::kNoCell, tool);
}

TEST(BoustrophedonTest, AnOpenRoomIsOneCellWithEvenlySpacedLanes) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(40, 30);
  ASSERT_TRUE(decompose(b, m).is_ok());
  expect_partition(b, m);
  ASSERT_EQ(b.cell_count(), 1u);
  // 39 columns between the outer lanes, at most 9 (0.45 m) apart: 6 lanes.
  ASSERT_EQ(b.cell(0).lanes, 6u);
  EXPECT_EQ(b.lane(0).column, 0);
  EXPECT_EQ(b.lane(5).column, 39);
  for (std::size_t k = 1; k < 6; ++k) {
    EXPECT_LE(b.lane(k).column - b.lane(k - 1).column, 9);
    EXPECT_EQ(b.lane(k).y0, 0);
    EXPECT_EQ(b.lane(k).y1, 29);
  }
}

TEST(BoustrophedonTest, AnObstacleSplitsTheRoomIntoFourCells) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(40, 30);
  m.fill(15, 10, 24, 19, 0);
  // Left of it, below it, above it, right of it (Choset's split and merge), with and without
  // the boundary-jump rule.
  for (const int step : {2, 1000}) {
    BoustrophedonConfig cfg = config();
    cfg.max_boundary_step = step;
    ASSERT_TRUE(decompose(b, m, cfg).is_ok());
    expect_partition(b, m);
    ASSERT_EQ(b.cell_count(), 4u);
    EXPECT_EQ(b.cell(0).x1, 14);
    EXPECT_EQ(b.cell(3).x0, 25);
  }
}

TEST(BoustrophedonTest, TwoRoomsAndTheirDoorAreSeparateCells) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(50, 30);
  m.fill(24, 0, 26, 29, 0);   // the wall
  m.fill(24, 12, 26, 17, 1);  // its door
  ASSERT_TRUE(decompose(b, m).is_ok());
  expect_partition(b, m);
  // The door's interval is no 1-to-1 change of connectivity, but its top and bottom jump: a cell
  // of its own, so no lane of a room is cut at the door's height.
  ASSERT_EQ(b.cell_count(), 3u);
  EXPECT_EQ(b.cell(1).x0, 24);
  EXPECT_EQ(b.cell(1).x1, 26);
  // Without the jump rule the three are one cell.
  BoustrophedonConfig loose = config();
  loose.max_boundary_step = 1000;
  ASSERT_TRUE(decompose(b, m, loose).is_ok());
  EXPECT_EQ(b.cell_count(), 1u);
}

TEST(BoustrophedonTest, RandomMasksArePartitionedExactly) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 1024, 4096).is_ok());
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Mask m = random_mask(seed);
    ASSERT_TRUE(decompose(b, m).is_ok());
    EXPECT_GT(b.cell_count(), 3u);
    expect_partition(b, m);
  }
}

// Lanes spread in each cell: every route alone sweeps its cell. Lanes on the map's grid: an
// open border is swept from the cell beyond it, so every cell is swept by the routes together.
TEST(BoustrophedonTest, EveryRouteSweepsItsCellWithTheToolWidth) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(50, 36);
  m.fill(15, 10, 24, 19, 0);
  m.fill(35, 0, 37, 35, 0);
  m.fill(35, 15, 37, 22, 1);
  // U-turns of half the lane spacing, and tighter ones.
  for (const double radius : {0.0, 0.1}) {
    BoustrophedonConfig cfg = config(radius);
    cfg.lane_grid = false;
    ASSERT_TRUE(decompose(b, m, cfg).is_ok());
    ASSERT_GE(b.cell_count(), 6u);
    for (std::size_t k = 0; k < b.cell_count(); ++k) {
      for (std::uint8_t e = 0; e < 4; ++e) {
        SCOPED_TRACE("radius " + std::to_string(radius) + " cell " + std::to_string(k) + " entry " +
                     std::to_string(e));
        const CellVisit v{std::uint16_t(k), e};
        EXPECT_EQ(route_coverage(b, m, v, 0.5), 1.0);
      }
    }
    cfg.lane_grid = true;
    ASSERT_TRUE(decompose(b, m, cfg).is_ok());
    EXPECT_EQ(all_routes_coverage(b, m, 0.5), 1.0) << "radius " << radius;
  }
}

// Beside a block (split into cells left, below, above and right of it) the cells below and
// above start at the block's first column, whose left neighbour is the free cell on the left:
// they lay no lane of their own there, and every lane is at least half the spacing from the
// next one across the border; lane_grid false lays one on each side of it.
TEST(BoustrophedonTest, AnOpenBorderIsSweptFromTheGridNotFromBothSides) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(41, 30);
  m.fill(13, 10, 26, 19, 0);
  const auto columns = [&]() {
    std::vector<int> c;
    for (std::size_t k = 0; k < b.lane_count(); ++k) c.push_back(b.lane(k).column);
    return c;
  };
  BoustrophedonConfig cfg = config();
  cfg.lane_grid = false;
  ASSERT_TRUE(decompose(b, m, cfg).is_ok());
  ASSERT_EQ(b.cell_count(), 4u);
  const std::vector<int> spread = columns();
  EXPECT_EQ(std::count(spread.begin(), spread.end(), 12), 1);  // the left cell's last
  EXPECT_EQ(std::count(spread.begin(), spread.end(), 13), 2);  // below's and above's first
  cfg.lane_grid = true;
  ASSERT_TRUE(decompose(b, m, cfg).is_ok());
  ASSERT_EQ(b.cell_count(), 4u);
  const std::vector<int> grid = columns();
  EXPECT_LT(grid.size(), spread.size());
  EXPECT_EQ(std::count(grid.begin(), grid.end(), 12), 1);  // the left cell faces the block
  EXPECT_EQ(std::count(grid.begin(), grid.end(), 13), 0);
  for (std::size_t k = 0; k < b.cell_count(); ++k) {
    const CoverCell& c = b.cell(k);
    for (std::uint32_t i = 1; i < c.lanes; ++i) {
      const int gap = b.lane(c.first_lane + i).column - b.lane(c.first_lane + i - 1).column;
      EXPECT_GE(gap, 5) << "cell " << k;  // half of 9 columns, rounded up
      EXPECT_LE(gap, 9) << "cell " << k;
    }
  }
  // Across the left border of the cells below and above: the left cell's lane at column 12,
  // theirs on the grid at 18 (2 x 9), 6 apart.
  EXPECT_EQ(b.lane(b.cell(1).first_lane).column, 18);
  EXPECT_EQ(all_routes_coverage(b, m, 0.5), 1.0);
}

TEST(BoustrophedonTest, RoutesStartAndEndAtTheVisitsCornersAndReverse) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(41, 30);
  ASSERT_TRUE(decompose(b, m, config(0.0)).is_ok());
  StaticVector<Vec2, 1024> r, back;
  for (std::uint8_t e = 0; e < 4; ++e) {
    const CellVisit v{0, e};
    ASSERT_TRUE(b.route(v, r));
    EXPECT_LT((r[0] - b.entry_point(v)).norm(), 1e-9);
    EXPECT_LT((r.back() - b.exit_point(v)).norm(), 1e-9);
    ASSERT_TRUE(b.route(b.reversed(v), back));
    ASSERT_EQ(back.size(), r.size());
    for (std::size_t i = 0; i < r.size(); ++i)
      EXPECT_LT((back[i] - r[r.size() - 1 - i]).norm(), 1e-9);
    // Every point inside the free cells, the half-circle U-turns included.
    for (const Vec2& p : r) {
      const int x = int(std::floor(p.x() / kRes)), y = int(std::floor(p.y() / kRes));
      EXPECT_NE(b.label(x, y), Boustrophedon::kNoCell) << p.transpose();
    }
  }
}

// The U-turn the coverage mission lays to join a cell onto the one before it is the route's own:
// a route rebuilt from its entry point, u_turn() between each pair of lanes (within their join
// bounds) and its last lane's end equals route() to the bit, and append_route() adds a route
// after what a buffer holds. Between lanes farther apart than two radii the turn has a straight
// across; closer than a quarter cell, it is straight across at the end.
TEST(BoustrophedonTest, AUTurnLaidAloneIsTheOneTheRouteLaysBetweenItsLanes) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(40, 30);
  m.fill(12, 0, 14, 9, 0);  // a wall's end from below: lanes of unequal length
  ASSERT_TRUE(decompose(b, m, config(0.0)).is_ok());
  StaticVector<Vec2, 1024> r, rebuilt, appended;
  int checked = 0;
  for (std::size_t c = 0; c < b.cell_count(); ++c) {
    const CoverCell& cell = b.cell(c);
    if (cell.single_pass || cell.lanes < 2) continue;
    for (std::uint8_t e = 0; e < 4; ++e) {
      const CellVisit v{std::uint16_t(c), e};
      ASSERT_TRUE(b.route(v, r));
      rebuilt.clear();
      rebuilt.push_back(b.entry_point(v));
      bool up = (e & 1) == 0;
      for (std::size_t k = 0; k + 1 < cell.lanes; ++k) {
        const std::size_t ia = (e & 2) != 0 ? cell.lanes - 1 - k : k;
        const std::size_t ib = (e & 2) != 0 ? ia - 1 : ia + 1;
        const CoverLane& la = b.lane(cell.first_lane + ia);
        const CoverLane& lb = b.lane(cell.first_lane + ib);
        const CoverLane& left = la.column < lb.column ? la : lb;
        ASSERT_TRUE(b.u_turn(la.x, lb.x, up, left.top_join_m, left.bottom_join_m, rebuilt));
        up = !up;
      }
      rebuilt.push_back(b.exit_point(v));
      ASSERT_EQ(rebuilt.size(), r.size()) << "cell " << c << " entry " << int(e);
      for (std::size_t i = 0; i < r.size(); ++i) {
        EXPECT_EQ(rebuilt[i].x(), r[i].x());
        EXPECT_EQ(rebuilt[i].y(), r[i].y());
      }
      appended.clear();
      appended.push_back(Vec2(-1.0, -1.0));
      ASSERT_TRUE(b.append_route(v, appended));
      ASSERT_EQ(appended.size(), r.size() + 1);
      for (std::size_t i = 0; i < r.size(); ++i) EXPECT_EQ(appended[i + 1], r[i]);
      ++checked;
    }
  }
  EXPECT_GE(checked, 8);  // two cells of lanes at least, every corner
  // Farther apart than two radii (0.45 m spacing: r 0.225): two quarter arcs and a straight.
  StaticVector<Vec2, 64> t;
  ASSERT_TRUE(b.u_turn(0.5, 1.3, true, 1.0, 0.0, t));
  EXPECT_LT((t[0] - Vec2(0.5, 1.0 - 0.225)).norm(), 1e-12);
  EXPECT_LT((t.back() - Vec2(1.3, 1.0 - 0.225)).norm(), 1e-12);
  double top = -1.0, longest = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    top = std::max(top, t[i].y());
    EXPECT_GE(t[i].x(), 0.5 - 1e-12);
    EXPECT_LE(t[i].x(), 1.3 + 1e-12);
    if (i > 0) longest = std::max(longest, (t[i] - t[i - 1]).norm());
  }
  EXPECT_NEAR(top, 1.0, 1e-12);
  EXPECT_NEAR(longest, 0.8 - 2 * 0.225, 1e-12);  // the straight across the top
  // Closer than a quarter cell: straight across at the bottom when driving down.
  t.clear();
  ASSERT_TRUE(b.u_turn(0.5, 0.51, false, 1.0, 0.0, t));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0], Vec2(0.5, 0.0));
  EXPECT_EQ(t[1], Vec2(0.51, 0.0));
}

// A strip shorter than the lane spacing across the sweep line: one pass along its middle, not a
// zigzag of U-turns tighter than its lanes are long; a room with long lanes keeps its U-turns.
TEST(BoustrophedonTest, AStripShorterThanTheSpacingIsOnePassThroughItsMiddle) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(41, 6);  // 2.05 x 0.3 m, lanes 0.25 m long (spacing 0.45 m)
  ASSERT_TRUE(decompose(b, m).is_ok());
  ASSERT_EQ(b.cell_count(), 1u);
  EXPECT_TRUE(b.cell(0).single_pass);
  StaticVector<Vec2, 1024> r;
  for (std::uint8_t e = 0; e < 4; ++e) {
    const CellVisit v{0, e};
    ASSERT_TRUE(b.route(v, r));
    EXPECT_EQ(r.size(), 41u);  // a point per column
    for (const Vec2& p : r) EXPECT_NEAR(p.y(), 0.15, 1e-9);
    EXPECT_LT((r[0] - b.entry_point(v)).norm(), 1e-9);
    EXPECT_LT((r.back() - b.exit_point(v)).norm(), 1e-9);
    EXPECT_LT((b.exit_point(b.reversed(v)) - b.entry_point(v)).norm(), 1e-9);
  }
  EXPECT_EQ(route_coverage(b, m, CellVisit{0, 0}, 0.34), 1.0);
  Mask tall(41, 12);  // lanes 0.55 m long: a boustrophedon
  ASSERT_TRUE(decompose(b, tall).is_ok());
  EXPECT_FALSE(b.cell(0).single_pass);
}

TEST(BoustrophedonTest, RandomRoutesStayInTheirCellsAndSweepNearlyAllOfThem) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 1024, 4096).is_ok());
  double worst = 1.0;
  StaticVector<Vec2, 4096> route;
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    const Mask m = random_mask(seed);
    ASSERT_TRUE(decompose(b, m).is_ok());
    for (std::size_t k = 0; k < b.cell_count(); ++k) {
      // Every point of the route, U-turns included, on a free cell of its own cell.
      ASSERT_TRUE(b.route(CellVisit{std::uint16_t(k), 0}, route));
      for (std::size_t i = 1; i < route.size(); ++i) {
        for (int s = 0; s <= 10; ++s) {
          const Vec2 p = route[i - 1] + (route[i] - route[i - 1]) * (s / 10.0);
          const int x = int(std::floor(p.x() / kRes)), y = int(std::floor(p.y() / kRes));
          ASSERT_EQ(b.label(x, y), k) << "seed " << seed << " at " << p.transpose();
        }
      }
    }
    worst = std::fmin(worst, all_routes_coverage(b, m, 0.5));
  }
  // Cells bounded by specks and slanted block edges lose a little at their lane ends.
  EXPECT_GT(worst, 0.97);
}

TEST(BoustrophedonTest, TheTourIsNoWorseThanTheInputOrder) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 1024, 4096).is_ok());
  int strictly_better = 0;
  for (std::uint32_t seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Mask m = random_mask(seed);
    ASSERT_TRUE(decompose(b, m).is_ok());
    const std::size_t n = b.cell_count();
    std::vector<CellVisit> plain(n);
    for (std::size_t k = 0; k < n; ++k) plain[k] = CellVisit{std::uint16_t(k), 0};
    const Vec2 start(0.3, 0.3);
    const double input = b.tour_cost(start, plain.data(), n);
    const double cost = b.order(start);
    EXPECT_NEAR(cost, b.tour_cost(start, b.tour(), n), 1e-6);
    EXPECT_LE(cost, input + 1e-9);
    if (cost < 0.8 * input) ++strictly_better;
    std::vector<int> seen(n, 0);
    for (std::size_t k = 0; k < n; ++k) ++seen[b.tour()[k].cell];
    for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(seen[k], 1);
  }
  EXPECT_GT(strictly_better, 20);
}

TEST(BoustrophedonTest, GapsFollowTheFreeSpaceThroughTheDoor) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  Mask m(50, 30);
  m.fill(24, 0, 26, 29, 0);
  m.fill(24, 0, 26, 3, 1);   // the door at the bottom
  m.fill(0, 14, 23, 15, 0);  // a wall across the left room: two cells there
  ASSERT_TRUE(decompose(b, m).is_ok());
  const std::uint16_t top_left = b.label(5, 25), right = b.label(40, 25);
  const std::uint16_t bottom_left = b.label(5, 5);
  EXPECT_EQ(b.gap_m(bottom_left, bottom_left), 0.0);
  // Through the door at the bottom, then up: 14 rows and the door's columns at least.
  EXPECT_GT(b.gap_m(top_left, right), 10 * kRes);
  EXPECT_LE(b.gap_m(bottom_left, b.label(25, 1)), kRes);
}

TEST(BoustrophedonTest, AnAreaWithNoFreeCellIsAClearError) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 64, 256).is_ok());
  const Status s = decompose(b, Mask(30, 20, 0));
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("no free cell"), std::string::npos) << s.message();
  EXPECT_EQ(b.cell_count(), 0u);
}

TEST(BoustrophedonTest, MoreCellsOrLanesThanTheBuffersHoldIsAClearError) {
  Boustrophedon small_cells;
  ASSERT_TRUE(small_cells.init(100, 100, 3, 256).is_ok());
  Mask m(40, 30);
  m.fill(15, 10, 24, 19, 0);
  Status s = decompose(small_cells, m);
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("coverage.max_cells"), std::string::npos) << s.message();
  Boustrophedon small_lanes;
  ASSERT_TRUE(small_lanes.init(100, 100, 64, 5).is_ok());
  s = decompose(small_lanes, Mask(40, 30));
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("coverage.max_lanes"), std::string::npos) << s.message();
  Boustrophedon small_grid;
  ASSERT_TRUE(small_grid.init(20, 20, 64, 256).is_ok());
  EXPECT_FALSE(decompose(small_grid, Mask(40, 30)).is_ok());
}

TEST(BoustrophedonTest, PlanningDoesNotAllocate) {
  Boustrophedon b;
  ASSERT_TRUE(b.init(100, 100, 1024, 4096).is_ok());
  const Mask m = random_mask(7);
  static StaticVector<Vec2, 4096> route;
  alloc::begin_window();
  const bool ok = decompose(b, m).is_ok();
  b.order(Vec2(0.5, 0.5));
  for (std::size_t k = 0; k < b.cell_count(); ++k) b.route(b.tour()[k], route);
  alloc::end_window();
  ASSERT_TRUE(ok);
  EXPECT_EQ(alloc::count_in_windows(), 0u);
}

// ---- the coverage area, from a static map ----

OccupancyGrid room_map(int nx, int ny, std::vector<std::uint8_t>& cells) {
  cells.assign(std::size_t(nx * ny), cost::kFree);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      if (x < 2 || y < 2 || x >= nx - 2 || y >= ny - 2)
        cells[std::size_t(y * nx + x)] = cost::kLethal;
  OccupancyGrid g(std::size_t(nx * ny));
  return g;
}

TEST(CoverageAreaTest, CentreCellsKeepTheRadiusAndTheToolReachesTheWalls) {
  std::vector<std::uint8_t> cells;
  OccupancyGrid map = room_map(40, 30, cells);
  MapInfo info;
  info.nx = 40;
  info.ny = 30;
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  CoverageArea area(40 * 30);
  CoverageAreaConfig cfg;  // radius 0.25 (5 cells), tool 0.5, reach 0.225
  ASSERT_TRUE(area.build(map, cfg).is_ok());
  // The wall's last cell is column 1: centre cells from column 7 (6 cells away) on.
  EXPECT_EQ(area.centre()[10 * 40 + 6], 0);
  EXPECT_EQ(area.centre()[10 * 40 + 7], 1);
  EXPECT_EQ(area.centre_cells(), std::size_t((40 - 14) * (30 - 14)));
  // The tool reaches 4.5 cells from the centre cells [7, 32] x [7, 22]: every free cell but the
  // row along the walls (5 cells away: under the tool's very edge) and the corners beyond the
  // reach, each anchored on a centre cell within the reach.
  EXPECT_EQ(area.coverable_cells(), std::size_t(34 * 24 - 4 * 3));
  for (int y = 0; y < 30; ++y) {
    for (int x = 0; x < 40; ++x) {
      const std::size_t k = std::size_t(y * 40 + x);
      const double dx = std::fmax(0.0, std::fmax(7.0 - x, x - 32.0));
      const double dy = std::fmax(0.0, std::fmax(7.0 - y, y - 22.0));
      const bool inner = std::hypot(dx, dy) <= 4.5;
      EXPECT_EQ(area.coverable()[k] != 0, inner) << x << "," << y;
      if (area.coverable()[k] == 0) continue;
      const std::int32_t a = area.anchor(k);
      ASSERT_GE(a, 0);
      EXPECT_EQ(area.centre()[a], 1);
      EXPECT_LE(std::hypot(a % 40 - x, a / 40 - y) * kRes, area.reach_m() + 1e-9);
    }
  }
}

TEST(CoverageAreaTest, ComponentsAndPolygonsLimitTheArea) {
  std::vector<std::uint8_t> cells;
  OccupancyGrid map = room_map(60, 30, cells);
  for (int y = 0; y < 30; ++y) cells[std::size_t(y * 60 + 30)] = cost::kLethal;  // closed wall
  MapInfo info;
  info.nx = 60;
  info.ny = 30;
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  CoverageArea area(60 * 30);
  CoverageAreaConfig cfg;
  ASSERT_TRUE(area.build(map, cfg).is_ok());
  const std::size_t both = area.coverable_cells();
  EXPECT_FALSE(area.keep_component(3, 3));  // no centre cell
  ASSERT_TRUE(area.keep_component(15, 15));
  EXPECT_GT(area.coverable_cells(), 0u);
  EXPECT_LT(area.coverable_cells(), both);
  for (int y = 0; y < 30; ++y)
    for (int x = 30; x < 60; ++x) EXPECT_EQ(area.coverable()[y * 60 + x], 0) << x << "," << y;
  // A polygon round the left half of the left room.
  const Vec2 poly[4] = {{0.0, 0.0}, {0.75, 0.0}, {0.75, 1.5}, {0.0, 1.5}};
  cfg.polygon = poly;
  cfg.polygon_size = 4;
  ASSERT_TRUE(area.build(map, cfg).is_ok());
  for (int y = 0; y < 30; ++y)
    for (int x = 15; x < 60; ++x) EXPECT_EQ(area.coverable()[y * 60 + x], 0) << x << "," << y;
  EXPECT_GT(area.coverable_cells(), 0u);
}

// Measured to an occupied cell's square, a corner (a door jamb) is as far as a wall's face:
// cells beside it that are clear by centres are not by the square.
TEST(CoverageAreaTest, BoxDistanceKeepsTheRadiusFromACornerAsFromAFace) {
  std::vector<std::uint8_t> cells;
  OccupancyGrid map = room_map(40, 30, cells);
  cells[std::size_t(15 * 40 + 20)] = cost::kLethal;  // a post at (20, 15)
  MapInfo info;
  info.nx = 40;
  info.ny = 30;
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  CoverageArea area(40 * 30);
  CoverageAreaConfig cfg;
  cfg.robot_radius_m = 0.1;  // 2 cells
  ASSERT_TRUE(area.build(map, cfg).is_ok());
  const auto centre = [&](int x, int y) { return area.centre()[std::size_t(y * 40 + x)] != 0; };
  EXPECT_FALSE(centre(22, 15));  // 2 cells: within by both
  EXPECT_TRUE(centre(22, 16));   // centres 2.24 cells apart
  EXPECT_TRUE(centre(22, 17));
  cfg.box_distance = true;
  ASSERT_TRUE(area.build(map, cfg).is_ok());
  EXPECT_FALSE(centre(22, 15));
  EXPECT_FALSE(centre(22, 16));  // 1.58 cells from the post's square
  EXPECT_TRUE(centre(22, 17));   // 2.12 cells from its corner
  EXPECT_TRUE(centre(23, 15));   // 2.5 cells from its face
  // A wall's face: the same centre cells either way (the wall's last cell is column 1).
  EXPECT_FALSE(centre(3, 10));
  EXPECT_TRUE(centre(4, 10));
}

TEST(CoverageAreaTest, AMapWithNoRoomForTheRobotIsAClearError) {
  std::vector<std::uint8_t> cells;
  OccupancyGrid map = room_map(12, 12, cells);  // 8 x 8 free cells: 0.4 m, the robot 0.5 m
  MapInfo info;
  info.nx = 12;
  info.ny = 12;
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  CoverageArea area(12 * 12);
  const Status s = area.build(map, CoverageAreaConfig{});
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("no free cell"), std::string::npos) << s.message();
  EXPECT_FALSE(area.build(OccupancyGrid(), CoverageAreaConfig{}).is_ok());
}

}  // namespace
}  // namespace carril::fw
