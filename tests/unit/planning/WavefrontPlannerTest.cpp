#include "firmware/planning/WavefrontPlanner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <queue>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/planning/PathWaypoints.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

using Path = StaticVector<GridCell, 4096>;

struct Grid {
  int nx, ny;
  std::vector<std::uint8_t> c;
  Grid(int w, int h, std::uint8_t fill = cost::kFree) : nx(w), ny(h), c(std::size_t(w * h), fill) {}
  std::uint8_t& at(int x, int y) { return c[std::size_t(y * nx + x)]; }
  std::uint8_t at(int x, int y) const { return c[std::size_t(y * nx + x)]; }
};

WavefrontConfig config(double weight = 3.0, bool allow_unknown = false) {
  WavefrontConfig cfg;
  cfg.cost_weight = weight;
  cfg.allow_unknown = allow_unknown;
  return cfg;
}

// Plans over the whole grid in one call and extracts the path from (sx, sy).
PathResult plan(WavefrontPlanner& p, const Grid& g, int sx, int sy, int gx, int gy, Path& out) {
  EXPECT_EQ(p.start(g.c.data(), g.nx, g.ny, gx, gy), WavefrontStatus::Running);
  EXPECT_EQ(p.step(0xFFFFFFFFu), WavefrontStatus::Done);
  return p.extract_path(sx, sy, out);
}

// ---- an independent oracle: textbook Dijkstra in double over the same rules ----

bool oracle_passable(std::uint8_t c, const WavefrontConfig& cfg) {
  return c <= 252 || (c == 255 && cfg.allow_unknown);
}
std::uint8_t oracle_cost(std::uint8_t c, const WavefrontConfig& cfg) {
  return c == 255 ? cfg.unknown_cost : c;
}
// Can the robot step from a to b (neighbours)? b passable, and a diagonal not between two walls.
bool oracle_step_ok(const Grid& g, int ax, int ay, int bx, int by, const WavefrontConfig& cfg) {
  if (bx < 0 || by < 0 || bx >= g.nx || by >= g.ny) return false;
  if (!oracle_passable(g.at(bx, by), cfg)) return false;
  if (ax != bx && ay != by) {
    const bool a_open = oracle_passable(g.at(bx, ay), cfg);
    const bool b_open = oracle_passable(g.at(ax, by), cfg);
    if (!a_open && !b_open) return false;
  }
  return true;
}
double oracle_weight(const Grid& g, int ax, int ay, int bx, int by, const WavefrontConfig& cfg) {
  const double len = (ax != bx && ay != by) ? std::sqrt(2.0) : 1.0;
  return len * (1.0 + cfg.cost_weight * oracle_cost(g.at(bx, by), cfg) / 252.0);
}

// Cost from every cell to the goal (robot moves toward the goal), infinity when cut off.
std::vector<double> oracle_field(const Grid& g, int gx, int gy, const WavefrontConfig& cfg) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(g.c.size(), inf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  d[std::size_t(gy * g.nx + gx)] = 0.0;
  q.push({0.0, gy * g.nx + gx});
  while (!q.empty()) {
    auto [dv, v] = q.top();
    q.pop();
    if (dv > d[std::size_t(v)]) continue;
    const int vx = v % g.nx, vy = v / g.nx;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int ux = vx + dx, uy = vy + dy;
        if ((dx == 0 && dy == 0) || ux < 0 || uy < 0 || ux >= g.nx || uy >= g.ny) continue;
        if (!oracle_passable(g.at(ux, uy), cfg)) continue;  // the robot starts its step on u
        if (!oracle_step_ok(g, ux, uy, vx, vy, cfg)) continue;
        const double nd = dv + oracle_weight(g, ux, uy, vx, vy, cfg);
        const std::size_t ui = std::size_t(uy * g.nx + ux);
        if (nd < d[ui]) {
          d[ui] = nd;
          q.push({nd, int(ui)});
        }
      }
    }
  }
  return d;
}

// Cost of a path the way the oracle counts it; -1 when a step is not allowed.
double path_cost(const Grid& g, const Path& p, const WavefrontConfig& cfg) {
  double sum = 0.0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const GridCell a = p[i - 1], b = p[i];
    if (std::abs(a.x - b.x) > 1 || std::abs(a.y - b.y) > 1 || (a.x == b.x && a.y == b.y))
      return -1.0;
    if (!oracle_step_ok(g, a.x, a.y, b.x, b.y, cfg)) return -1.0;
    sum += oracle_weight(g, a.x, a.y, b.x, b.y, cfg);
  }
  return sum;
}

Grid random_grid(unsigned seed, int nx, int ny, double obstacle_fraction, bool with_unknown) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> graded(0, 252);
  Grid g(nx, ny);
  for (auto& c : g.c) {
    const double r = u(rng);
    if (r < obstacle_fraction) {
      c = r < obstacle_fraction * 0.5 ? cost::kLethal : cost::kInscribed;
    } else if (with_unknown && r < obstacle_fraction + 0.1) {
      c = cost::kUnknown;
    } else {
      c = u(rng) < 0.5 ? cost::kFree : std::uint8_t(graded(rng));
    }
  }
  return g;
}

// ---- tests ----

TEST(WavefrontPlannerTest, ConfigValidateNamesTheKey) {
  WavefrontConfig cfg;
  EXPECT_TRUE(cfg.validate().is_ok());
  cfg.unknown_cost = 253;
  EXPECT_NE(std::string(cfg.validate().message()).find("planner.unknown_cost"), std::string::npos)
      << cfg.validate().message();
  cfg = WavefrontConfig{};
  cfg.cost_weight = -1.0;
  EXPECT_NE(std::string(cfg.validate().message()).find("planner.cost_weight"), std::string::npos);
  WavefrontPlanner p;
  EXPECT_FALSE(p.init(10, 10, cfg));
  EXPECT_FALSE(p.init(0, 10, WavefrontConfig{}));
}

TEST(WavefrontPlannerTest, StraightCorridor) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(20, 5, config()));
  Grid g(20, 5);
  for (int x = 0; x < 20; ++x) g.at(x, 0) = g.at(x, 4) = cost::kLethal;
  Path path;
  ASSERT_EQ(plan(p, g, 1, 2, 18, 2, path), PathResult::Ok);
  ASSERT_EQ(path.size(), 18u);
  for (std::size_t i = 0; i < path.size(); ++i) {
    EXPECT_EQ(path[i].x, 1 + int(i));
    EXPECT_EQ(path[i].y, 2);
  }
  EXPECT_FLOAT_EQ(p.cost_to_goal(1, 2), 17.0f);
  EXPECT_FLOAT_EQ(p.cost_to_goal(18, 2), 0.0f);
  EXPECT_FALSE(p.reachable(5, 0));  // a wall
}

TEST(WavefrontPlannerTest, PathGoesAroundAWall) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(20, 20, config()));
  Grid g(20, 20);
  for (int y = 0; y < 16; ++y) g.at(10, y) = cost::kLethal;
  Path path;
  ASSERT_EQ(plan(p, g, 2, 2, 17, 2, path), PathResult::Ok);
  int top = 0;
  for (const GridCell& c : path) {
    EXPECT_NE(g.at(c.x, c.y), cost::kLethal) << c.x << "," << c.y;
    if (c.y > top) top = c.y;
  }
  EXPECT_GE(top, 16);  // over the wall's end
  EXPECT_EQ(path.back().x, 17);
  EXPECT_EQ(path.back().y, 2);
  const auto oracle = oracle_field(g, 17, 2, config());
  EXPECT_NEAR(path_cost(g, path, config()), oracle[2 * 20 + 2], 1e-4);
}

TEST(WavefrontPlannerTest, EnclosedGoalHasNoPath) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(20, 20, config()));
  Grid g(20, 20);
  for (int i = 8; i <= 12; ++i) g.at(i, 8) = g.at(i, 12) = g.at(8, i) = g.at(12, i) = cost::kLethal;
  Path path;
  EXPECT_EQ(plan(p, g, 2, 2, 10, 10, path), PathResult::Unreachable);
  EXPECT_TRUE(path.empty());
  EXPECT_FALSE(p.reachable(2, 2));
  EXPECT_EQ(p.cost_to_goal(2, 2), WavefrontPlanner::kInfinity);
  EXPECT_TRUE(p.reachable(11, 11));
  EXPECT_EQ(p.expanded(), 9u);  // the 3 x 3 inside only
}

TEST(WavefrontPlannerTest, UnknownIsAWallUnlessAllowed) {
  Grid g(10, 3, cost::kFree);
  for (int y = 0; y < 3; ++y) g.at(5, y) = cost::kUnknown;
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(10, 3, config(3.0, false)));
  Path path;
  EXPECT_EQ(plan(p, g, 0, 1, 9, 1, path), PathResult::Unreachable);
  p.set_config(config(3.0, true));
  ASSERT_EQ(plan(p, g, 0, 1, 9, 1, path), PathResult::Ok);
  // 9 steps, one of them into an unknown cell at unknown_cost 200.
  EXPECT_NEAR(p.cost_to_goal(0, 1), 8.0 + (1.0 + 3.0 * 200.0 / 252.0), 1e-5);
}

TEST(WavefrontPlannerTest, BadGoalsAreRejected) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(10, 10, config()));
  Grid g(10, 10);
  g.at(4, 4) = cost::kLethal;
  g.at(5, 5) = cost::kInscribed;
  g.at(6, 6) = cost::kUnknown;
  EXPECT_EQ(p.start(g.c.data(), 10, 10, 4, 4), WavefrontStatus::GoalBlocked);
  EXPECT_EQ(p.start(g.c.data(), 10, 10, 5, 5), WavefrontStatus::GoalBlocked);
  EXPECT_EQ(p.start(g.c.data(), 10, 10, 6, 6), WavefrontStatus::GoalBlocked);
  EXPECT_EQ(p.start(g.c.data(), 10, 10, 10, 3), WavefrontStatus::GoalOutside);
  EXPECT_EQ(p.start(g.c.data(), 10, 10, -1, 3), WavefrontStatus::GoalOutside);
  EXPECT_EQ(p.step(1000), WavefrontStatus::GoalOutside);  // nothing runs
  EXPECT_EQ(p.start(g.c.data(), 11, 10, 1, 1), WavefrontStatus::BadGrid);
  EXPECT_STREQ(to_string(WavefrontStatus::GoalBlocked), "goal in obstacle");
  Path path;
  EXPECT_EQ(p.extract_path(1, 1, path), PathResult::NotReady);
}

// A band of graded cost 200 across the straight line, open at both ends: the detour round it is
// longer than the straight line by about 3 cells.
TEST(WavefrontPlannerTest, CostWeightChoosesDetourOrShortcut) {
  Grid g(30, 11);
  for (int y = 1; y <= 9; ++y) g.at(14, y) = g.at(15, y) = 200;
  auto crosses_band = [&](const Path& path) {
    for (const GridCell& c : path)
      if (g.at(c.x, c.y) == 200) return true;
    return false;
  };
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(30, 11, config(3.0)));
  Path path;
  ASSERT_EQ(plan(p, g, 2, 5, 27, 5, path), PathResult::Ok);
  EXPECT_FALSE(crosses_band(path)) << "weight 3: the band costs 2 x 2.4 extra, the detour ~3";
  p.set_config(config(0.5));
  ASSERT_EQ(plan(p, g, 2, 5, 27, 5, path), PathResult::Ok);
  EXPECT_TRUE(crosses_band(path)) << "weight 0.5: the band costs 2 x 0.4 extra";
  EXPECT_NEAR(p.cost_to_goal(2, 5), 23.0 + 2.0 * (1.0 + 0.5 * 200.0 / 252.0), 1e-4);
}

TEST(WavefrontPlannerTest, NoDiagonalBetweenTwoWalls) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(2, 2, config()));
  Grid g(2, 2);
  g.at(1, 0) = cost::kLethal;
  g.at(0, 1) = cost::kLethal;
  Path path;
  EXPECT_EQ(plan(p, g, 0, 0, 1, 1, path), PathResult::Unreachable);
  g.at(0, 1) = cost::kFree;  // one wall only: the diagonal is allowed
  ASSERT_EQ(plan(p, g, 0, 0, 1, 1, path), PathResult::Ok);
  EXPECT_EQ(path.size(), 2u);
  EXPECT_FLOAT_EQ(p.cost_to_goal(0, 0), std::sqrt(2.0f));
}

TEST(WavefrontPlannerTest, IncrementalStepsGiveTheSameFieldAndPath) {
  const Grid g = random_grid(7, 60, 50, 0.2, false);
  WavefrontPlanner once, chunked;
  ASSERT_TRUE(once.init(60, 50, config()));
  ASSERT_TRUE(chunked.init(60, 50, config()));
  ASSERT_EQ(once.start(g.c.data(), 60, 50, 3, 3), WavefrontStatus::Running);
  ASSERT_EQ(chunked.start(g.c.data(), 60, 50, 3, 3), WavefrontStatus::Running);
  ASSERT_EQ(once.step(0xFFFFFFFFu), WavefrontStatus::Done);
  int calls = 0;
  while (chunked.step(100) == WavefrontStatus::Running) {
    ++calls;
    EXPECT_EQ(chunked.expanded(), std::uint32_t(100 * calls));
  }
  EXPECT_GT(calls, 10);
  EXPECT_EQ(chunked.expanded(), once.expanded());
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 60; ++x) ASSERT_EQ(once.cost_to_goal(x, y), chunked.cost_to_goal(x, y));
  Path a, b;
  int far_x = 0, far_y = 0;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 60; ++x)
      if (once.reachable(x, y) && once.cost_to_goal(x, y) > once.cost_to_goal(far_x, far_y)) {
        far_x = x;
        far_y = y;
      }
  ASSERT_EQ(once.extract_path(far_x, far_y, a), PathResult::Ok);
  ASSERT_EQ(chunked.extract_path(far_x, far_y, b), PathResult::Ok);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].x == b[i].x && a[i].y == b[i].y);
}

// The field and every extracted path match a textbook Dijkstra on random grids with graded,
// inscribed, lethal and unknown cells.
TEST(WavefrontPlannerTest, MatchesBruteForceDijkstraOnRandomGrids) {
  int compared = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const bool unknown = seed % 2 == 0;
    const WavefrontConfig cfg = config(0.5 * seed, unknown);
    const Grid g = random_grid(seed, 45, 37, 0.25, unknown);
    WavefrontPlanner p;
    ASSERT_TRUE(p.init(45, 37, cfg));
    std::mt19937 rng(seed * 100);
    int gx = 0, gy = 0;
    do {
      gx = int(rng() % 45);
      gy = int(rng() % 37);
    } while (!oracle_passable(g.at(gx, gy), cfg));
    ASSERT_EQ(p.start(g.c.data(), 45, 37, gx, gy), WavefrontStatus::Running);
    ASSERT_EQ(p.step(0xFFFFFFFFu), WavefrontStatus::Done);
    const auto oracle = oracle_field(g, gx, gy, cfg);
    for (int y = 0; y < 37; ++y) {
      for (int x = 0; x < 45; ++x) {
        const double o = oracle[std::size_t(y * 45 + x)];
        const bool passable = oracle_passable(g.at(x, y), cfg);
        if (!passable || !std::isfinite(o)) {
          ASSERT_FALSE(p.reachable(x, y)) << "seed " << seed << " cell " << x << "," << y;
          continue;
        }
        ASSERT_TRUE(p.reachable(x, y)) << "seed " << seed << " cell " << x << "," << y;
        ASSERT_NEAR(p.cost_to_goal(x, y), o, 1e-5 * (1.0 + o)) << "seed " << seed;
        Path path;
        ASSERT_EQ(p.extract_path(x, y, path), PathResult::Ok);
        ASSERT_NEAR(path_cost(g, path, cfg), o, 1e-5 * (1.0 + o)) << "seed " << seed;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 5000);
}

TEST(WavefrontPlannerTest, EarlyExitStopsOnceTheStartIsFinal) {
  const Grid g = random_grid(3, 80, 80, 0.15, false);
  Grid clear = g;
  clear.at(10, 10) = clear.at(14, 12) = cost::kFree;
  WavefrontPlanner full, early;
  ASSERT_TRUE(full.init(80, 80, config()));
  ASSERT_TRUE(early.init(80, 80, config()));
  Path a, b;
  ASSERT_EQ(plan(full, clear, 14, 12, 10, 10, a), PathResult::Ok);
  ASSERT_EQ(early.start(clear.c.data(), 80, 80, 10, 10), WavefrontStatus::Running);
  early.set_start(14, 12);
  while (early.step(7) == WavefrontStatus::Running) {
  }
  EXPECT_EQ(early.status(), WavefrontStatus::Done);
  EXPECT_LT(early.expanded(), full.expanded() / 10);
  ASSERT_EQ(early.extract_path(14, 12, b), PathResult::Ok);
  EXPECT_EQ(early.cost_to_goal(14, 12), full.cost_to_goal(14, 12));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].x == b[i].x && a[i].y == b[i].y);
}

TEST(WavefrontPlannerTest, StartsFromARollingGridWindow) {
  RollingGrid<std::uint8_t> grid;
  ASSERT_TRUE(grid.init(40, 30, 0.05, cost::kFree));
  grid.recenter(3.33, -1.7);  // the storage wraps in both axes
  const Grid g = random_grid(11, 40, 30, 0.2, false);
  for (int ly = 0; ly < 30; ++ly)
    for (int lx = 0; lx < 40; ++lx) grid.local(lx, ly) = g.at(lx, ly);
  Grid goal_clear = g;
  goal_clear.at(20, 15) = cost::kFree;
  grid.local(20, 15) = cost::kFree;
  WavefrontPlanner from_window, from_array;
  ASSERT_TRUE(from_window.init(40, 30, config()));
  ASSERT_TRUE(from_array.init(40, 30, config()));
  ASSERT_EQ(from_window.start(grid, grid.origin_cx() + 20, grid.origin_cy() + 15),
            WavefrontStatus::Running);
  ASSERT_EQ(from_array.start(goal_clear.c.data(), 40, 30, 20, 15), WavefrontStatus::Running);
  from_window.step(0xFFFFFFFFu);
  from_array.step(0xFFFFFFFFu);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      ASSERT_EQ(from_window.cost_to_goal(x, y), from_array.cost_to_goal(x, y)) << x << "," << y;
  EXPECT_EQ(from_window.start(grid, grid.origin_cx() - 1, grid.origin_cy()),
            WavefrontStatus::GoalOutside);
}

TEST(WavefrontPlannerTest, NoAllocationAfterInit) {
  const Grid g = random_grid(5, 200, 200, 0.2, false);
  Grid clear = g;
  clear.at(100, 100) = clear.at(5, 5) = cost::kFree;
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(200, 200, config()));
  static Path path;
  const auto before = alloc::count_total();
  ASSERT_EQ(p.start(clear.c.data(), 200, 200, 100, 100), WavefrontStatus::Running);
  while (p.step(1000) == WavefrontStatus::Running) {
  }
  const PathResult r = p.extract_path(5, 5, path);
  EXPECT_EQ(alloc::count_total(), before);
  EXPECT_EQ(r, PathResult::Ok);
  auto* leak = new int(3);  // shows that counting is live
  EXPECT_GT(alloc::count_total(), before);
  delete leak;
}

TEST(WavefrontPlannerTest, PathTooLongForTheOutput) {
  WavefrontPlanner p;
  ASSERT_TRUE(p.init(50, 1, config()));
  Grid g(50, 1);
  StaticVector<GridCell, 10> small;
  ASSERT_EQ(p.start(g.c.data(), 50, 1, 49, 0), WavefrontStatus::Running);
  p.step(0xFFFFFFFFu);
  EXPECT_EQ(p.extract_path(0, 0, small), PathResult::TooLong);
}

TEST(PathWaypointsTest, KeepsOnlyTurnsAndEnds) {
  Path cells;
  for (int x = 0; x <= 4; ++x) cells.push_back({x, 0});      // east
  for (int i = 1; i <= 3; ++i) cells.push_back({4 + i, i});  // north-east
  cells.push_back({7, 4});                                   // north
  StaticVector<Vec2, 16> wp;
  ASSERT_TRUE(cells_to_waypoints(cells.begin(), cells.size(), -1.0, 2.0, 0.1, wp));
  ASSERT_EQ(wp.size(), 4u);
  EXPECT_NEAR(wp[0].x(), -0.95, 1e-12);
  EXPECT_NEAR(wp[0].y(), 2.05, 1e-12);
  EXPECT_NEAR(wp[1].x(), -1.0 + 4.5 * 0.1, 1e-12);  // the turn at (4, 0)
  EXPECT_NEAR(wp[2].x(), -1.0 + 7.5 * 0.1, 1e-12);  // the turn at (7, 3)
  EXPECT_NEAR(wp[2].y(), 2.0 + 3.5 * 0.1, 1e-12);
  EXPECT_NEAR(wp[3].y(), 2.0 + 4.5 * 0.1, 1e-12);
  StaticVector<Vec2, 2> tiny;
  EXPECT_FALSE(cells_to_waypoints(cells.begin(), cells.size(), 0.0, 0.0, 0.1, tiny));
}

}  // namespace
}  // namespace carril::fw
