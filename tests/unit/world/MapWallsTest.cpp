// Simulator walls from an occupancy map: the rectangles cover the occupied cells exactly once
// (random maps and the shipped ones), they are few, Box2D ray casts against the built body hit
// where a walk through the grid does, and a SimWorld built from a scenario with `map:` has them
// (its 2D lidar sees them, the robot collides with them).
#include "host_sim/world/MapWalls.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/mapping/CostValues.hpp"
#include "hal/Types.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

namespace cost = fw::cost;
using loader::OccupancyMapData;

std::string shipped(const char* name) {
  return std::string(CARRIL_SOURCE_DIR) + "/scenarios/maps/" + name + ".yaml";
}

OccupancyMapData load_shipped(const char* name) {
  loader::OccupancyMapLoad r = loader::load_occupancy_map(shipped(name), 1'000'000);
  EXPECT_TRUE(r.ok()) << r.error;
  return std::move(r.map);
}

std::uint8_t at(const OccupancyMapData& m, int i, int j) {
  return m.cells[std::size_t(j) * std::size_t(m.info.nx) + std::size_t(i)];
}

// A random nx x ny map at 0.05 m: a few solid blocks and lines on scattered noise, free,
// occupied and unknown cells.
OccupancyMapData random_map(std::mt19937& rng, int nx, int ny, double density) {
  OccupancyMapData m;
  m.info = {nx, ny, 0.05, -1.3, 0.45};
  m.cells.assign(std::size_t(nx) * std::size_t(ny), cost::kFree);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& c : m.cells) {
    const double v = u(rng);
    c = v < density ? cost::kLethal : v < density * 1.3 ? cost::kUnknown : cost::kFree;
  }
  std::uniform_int_distribution<int> xi(0, nx - 1), yj(0, ny - 1);
  for (int k = 0; k < 6; ++k) {
    const int i0 = xi(rng), i1 = std::min(nx, i0 + 1 + xi(rng) / 2);
    const int j0 = yj(rng), j1 = std::min(ny, j0 + 1 + yj(rng) / 2);
    for (int j = j0; j < j1; ++j) {
      for (int i = i0; i < i1; ++i)
        m.cells[std::size_t(j) * std::size_t(nx) + std::size_t(i)] = cost::kLethal;
    }
  }
  return m;
}

// Every rectangle's world extent lies on the cell grid and names its cell range; together they
// cover each occupied cell once and nothing else. The number of rectangles.
std::size_t expect_exact_cover(const OccupancyMapData& m, const std::vector<WallRect>& rects) {
  const fw::MapInfo& in = m.info;
  std::vector<int> covered(m.cells.size(), 0);
  auto index = [&](double v, double origin) {
    const double f = (v - origin) / in.resolution_m;
    EXPECT_NEAR(f, std::round(f), 1e-6) << "not on the grid: " << v;
    return int(std::lround(f));
  };
  for (const WallRect& r : rects) {
    const int i0 = index(r.min_x, in.origin_x_m), i1 = index(r.max_x, in.origin_x_m);
    const int j0 = index(r.min_y, in.origin_y_m), j1 = index(r.max_y, in.origin_y_m);
    EXPECT_EQ(i0, r.i0);
    EXPECT_EQ(i1, r.i1);
    EXPECT_EQ(j0, r.j0);
    EXPECT_EQ(j1, r.j1);
    EXPECT_TRUE(0 <= i0 && i0 < i1 && i1 <= in.nx && 0 <= j0 && j0 < j1 && j1 <= in.ny)
        << i0 << ".." << i1 << " x " << j0 << ".." << j1;
    for (int j = std::max(j0, 0); j < std::min(j1, in.ny); ++j) {
      for (int i = std::max(i0, 0); i < std::min(i1, in.nx); ++i) {
        ++covered[std::size_t(j) * std::size_t(in.nx) + std::size_t(i)];
      }
    }
  }
  std::size_t wrong = 0;
  for (std::size_t k = 0; k < covered.size(); ++k) {
    const int want = m.cells[k] == cost::kLethal ? 1 : 0;
    if (covered[k] != want && ++wrong <= 5) {
      ADD_FAILURE() << "cell (" << k % std::size_t(in.nx) << ", " << k / std::size_t(in.nx)
                    << ") value " << int(m.cells[k]) << " covered " << covered[k] << " times";
    }
  }
  EXPECT_EQ(wrong, 0U);
  return rects.size();
}

TEST(MapWalls, RandomMapsAreCoveredExactlyOnce) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const int nx = 1 + int(rng() % 40), ny = 1 + int(rng() % 40);
    const double density = (trial % 6) / 5.0;  // 0 (none) to 1 (all occupied)
    const OccupancyMapData m = random_map(rng, nx, ny, density);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_exact_cover(m, merge_occupied_cells(m));
  }
}

TEST(MapWalls, EmptyFullAndSingleCellMaps) {
  OccupancyMapData m;
  m.info = {7, 5, 0.1, 2.0, -3.0};
  m.cells.assign(35, cost::kFree);
  EXPECT_TRUE(merge_occupied_cells(m).empty());
  m.cells.assign(35, cost::kUnknown);
  EXPECT_TRUE(merge_occupied_cells(m).empty());
  m.cells.assign(35, cost::kLethal);
  auto rects = merge_occupied_cells(m);
  ASSERT_EQ(rects.size(), 1U);
  EXPECT_DOUBLE_EQ(rects[0].min_x, 2.0);
  EXPECT_DOUBLE_EQ(rects[0].max_x, 2.7);
  EXPECT_DOUBLE_EQ(rects[0].min_y, -3.0);
  EXPECT_DOUBLE_EQ(rects[0].max_y, -2.5);
  m.cells.assign(35, cost::kFree);
  m.cells[2 * 7 + 4] = cost::kLethal;  // cell (4, 2)
  rects = merge_occupied_cells(m);
  ASSERT_EQ(rects.size(), 1U);
  EXPECT_DOUBLE_EQ(rects[0].min_x, 2.4);
  EXPECT_DOUBLE_EQ(rects[0].max_x, 2.5);
  EXPECT_DOUBLE_EQ(rects[0].min_y, -2.8);
  EXPECT_DOUBLE_EQ(rects[0].max_y, -2.7);
}

TEST(MapWalls, MergesAlongTheBetterAxis) {
  // A comb: a bar along the bottom and five teeth up from it. Runs along rows merged upwards
  // give 6 rectangles, along columns 10; the same comb turned on its side the other way round.
  OccupancyMapData comb;
  comb.info = {9, 10, 0.05, 0.0, 0.0};
  comb.cells.assign(90, cost::kFree);
  for (int j = 0; j < 10; ++j) {
    for (int i = 0; i < 9; ++i) {
      if (j == 0 || i % 2 == 0) comb.cells[std::size_t(j * 9 + i)] = cost::kLethal;
    }
  }
  OccupancyMapData side;
  side.info = {10, 9, 0.05, 0.0, 0.0};
  side.cells.assign(90, cost::kFree);
  for (int j = 0; j < 9; ++j) {
    for (int i = 0; i < 10; ++i) side.cells[std::size_t(j * 10 + i)] = at(comb, j, i);
  }
  EXPECT_EQ(expect_exact_cover(comb, merge_occupied_cells(comb)), 6U);
  EXPECT_EQ(expect_exact_cover(side, merge_occupied_cells(side)), 6U);
}

TEST(MapWalls, ShippedMapsMergeIntoFewRectangles) {
  // Upper bounds a little above what the merge gives today (printed), far below the cells.
  for (const auto& [name, most] : {std::pair{"house", 60U}, {"warehouse", 40U}, {"city", 40U}}) {
    const OccupancyMapData m = load_shipped(name);
    std::size_t occupied = 0;
    for (std::uint8_t c : m.cells) occupied += c == cost::kLethal ? 1 : 0;
    const std::size_t n = expect_exact_cover(m, merge_occupied_cells(m));
    std::printf("%s: %zu occupied cells -> %zu rectangles\n", name, occupied, n);
    EXPECT_LE(n, most) << name;
  }
}

TEST(MapWalls, OneStaticBodyWithABoxPerRectangle) {
  const OccupancyMapData m = load_shipped("house");
  const std::vector<WallRect> rects = merge_occupied_cells(m);
  b2World world(b2Vec2(0.0F, 0.0F));
  const b2Body* body = add_map_walls(world, rects);
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(world.GetBodyCount(), 1);
  EXPECT_EQ(body->GetType(), b2_staticBody);
  std::size_t fixtures = 0;
  for (const b2Fixture* f = body->GetFixtureList(); f != nullptr; f = f->GetNext()) ++fixtures;
  EXPECT_EQ(fixtures, rects.size());
  EXPECT_EQ(add_map_walls(world, {}), nullptr);
  EXPECT_EQ(world.GetBodyCount(), 1);
}

// Cells a ray enters, in order, up to and including the first occupied one it crosses by more
// than kGraze (a ray that only clips a corner may hit or miss it in float arithmetic).
constexpr double kGraze = 1e-4;  // [m]
struct GridHit {
  double t = 0.0;      // distance to where the ray enters the cell [m]
  double chord = 0.0;  // length of the ray inside it [m]
};

std::vector<GridHit> grid_walk(const OccupancyMapData& m, double x, double y, double dx, double dy,
                               double range) {
  const fw::MapInfo& in = m.info;
  const double res = in.resolution_m, inf = std::numeric_limits<double>::infinity();
  int i = int(std::floor((x - in.origin_x_m) / res)),
      j = int(std::floor((y - in.origin_y_m) / res));
  const int si = dx > 0 ? 1 : -1, sj = dy > 0 ? 1 : -1;
  auto first = [&](double p, double o, int c, double d, int s) {
    if (std::abs(d) < 1e-12) return inf;
    return (o + (c + (s > 0 ? 1 : 0)) * res - p) / d;
  };
  double tx = first(x, in.origin_x_m, i, dx, si), ty = first(y, in.origin_y_m, j, dy, sj);
  const double stepx = std::abs(dx) < 1e-12 ? inf : res / std::abs(dx);
  const double stepy = std::abs(dy) < 1e-12 ? inf : res / std::abs(dy);
  std::vector<GridHit> hits;
  double t = 0.0;
  while (t < range && i >= 0 && j >= 0 && i < in.nx && j < in.ny) {
    const double exit = std::min({tx, ty, range});
    if (at(m, i, j) == cost::kLethal) {
      hits.push_back({t, exit - t});
      if (exit - t >= kGraze) break;
    }
    if (tx < ty) {
      t = tx;
      tx += stepx;
      i += si;
    } else {
      t = ty;
      ty += stepy;
      j += sj;
    }
  }
  return hits;
}

class Closest : public b2RayCastCallback {
 public:
  float ReportFixture(b2Fixture*, const b2Vec2&, const b2Vec2&, float fraction) override {
    best = std::min(best, fraction);
    return fraction;
  }
  float best = 2.0F;
};

// Rays from free cell centres in every direction: Box2D's hit is where the grid walk meets the
// first occupied cell (within 1 mm), or at one it only grazes; no hit where the grid has none.
void expect_rays_agree(const OccupancyMapData& m, std::uint32_t seed, int rays) {
  b2World world(b2Vec2(0.0F, 0.0F));
  add_map_walls(world, merge_occupied_cells(m));
  std::vector<std::size_t> free;
  for (std::size_t k = 0; k < m.cells.size(); ++k) {
    if (m.cells[k] == cost::kFree) free.push_back(k);
  }
  ASSERT_FALSE(free.empty());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  const fw::MapInfo& in = m.info;
  const double range = std::hypot(in.nx, in.ny) * in.resolution_m + 1.0;
  int hits = 0, grazes = 0;
  for (int k = 0; k < rays; ++k) {
    const std::size_t c = free[rng() % free.size()];
    const double x = in.origin_x_m + (double(c % std::size_t(in.nx)) + 0.5) * in.resolution_m;
    const double y = in.origin_y_m + (double(c / std::size_t(in.nx)) + 0.5) * in.resolution_m;
    const double a = angle(rng), dx = std::cos(a), dy = std::sin(a);
    Closest cb;
    world.RayCast(&cb, b2Vec2(float(x), float(y)),
                  b2Vec2(float(x + dx * range), float(y + dy * range)));
    const std::vector<GridHit> grid = grid_walk(m, x, y, dx, dy, range);
    const bool solid = !grid.empty() && grid.back().chord >= kGraze;
    grazes += int(grid.size()) - (solid ? 1 : 0);
    if (cb.best <= 1.0F) {
      ++hits;
      const double d = double(cb.best) * range;
      bool match = false;
      for (const GridHit& g : grid) match = match || std::abs(d - g.t) <= 1e-3;
      EXPECT_TRUE(match) << "ray from (" << x << ", " << y << ") at " << a << " rad: Box2D hits at "
                         << d << " m, the grid at "
                         << (solid ? std::to_string(grid.back().t) + " m" : "nothing");
    } else {
      EXPECT_FALSE(solid) << "ray from (" << x << ", " << y << ") at " << a
                          << " rad: Box2D hits nothing, the grid at " << grid.back().t << " m";
    }
  }
  std::printf("%d rays, %d hits, %d corner grazes\n", rays, hits, grazes);
}

TEST(MapWalls, RayCastsHitWhereTheGridWalkDoes) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    SCOPED_TRACE("random map " + std::to_string(trial));
    expect_rays_agree(random_map(rng, 30 + trial, 40 - trial, 0.08), 100 + trial, 300);
  }
  for (const char* name : {"house", "warehouse", "city"}) {
    SCOPED_TRACE(name);
    expect_rays_agree(load_shipped(name), 7, 2000);
  }
}

// A scenario in the shipped house: a Pioneer 3-AT at world (0, 0) in the hall, facing east.
Scenario house_scenario() {
  return test::load_text(R"(
name: house_map
duration_s: 1
map: )" + shipped("house") +
                         R"(
robot: {preset: pioneer3at, lidar: {noise_std_m: 0.0}}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-1, 0], [1, 0]]}]
)");
}

TEST(MapWalls, SimWorldLidarSeesTheMap) {
  const Scenario s = house_scenario();
  ASSERT_NE(s.map, nullptr);
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  hal::LaserScan scan;
  lidar.scan(world, scan);
  const RobotSpec& r = s.robot;
  ASSERT_EQ(scan.count, r.lidar.beams);
  int seen = 0;
  for (int k = 0; k < scan.count; ++k) {
    const double a = double(scan.angle_min_rad) + k * double(scan.angle_increment_rad);
    // The beam in float as the simulator casts it, walked through the grid in double.
    const double dx = std::cos(a), dy = std::sin(a);
    const std::vector<GridHit> grid =
        grid_walk(*s.map, r.lidar.x_m, r.lidar.y_m, dx, dy, r.lidar.range_max_m);
    const float got = scan.ranges_m[std::size_t(k)];
    if (grid.empty() || grid.back().chord < kGraze) {
      EXPECT_TRUE(std::isinf(got)) << "beam " << k << " at " << a << " rad: " << got;
      continue;
    }
    ++seen;
    EXPECT_NEAR(got, grid.back().t, 1e-3) << "beam " << k << " at " << a << " rad";
  }
  EXPECT_GT(seen, scan.count * 9 / 10);  // the hall's walls and doors all round
}

TEST(MapWalls, RobotCollidesWithTheMapsWalls) {
  // East along the hall from world (0, 0): the console table (plan x 9.45 = world 4.45, hall
  // y 3.8..4.7 = world -0.45..0.45) stops the body's front (0.254 m ahead of its centre).
  const Scenario s = house_scenario();
  SimWorld world(s);
  fw::DriveKinematics kin(drive_geometry(s.robot));
  float w[2];
  kin.inverse({0.5, 0.0, 0.0}, w);
  world.set_wheel_targets(w);
  for (int i = 0; i < 3000; ++i) world.step(0.005);  // 15 s: 7.5 m unobstructed
  EXPECT_EQ(world.collisions(), 1);
  EXPECT_NEAR(world.pose().x, 4.45 - 0.254, 0.03);
}

}  // namespace
}  // namespace carril::sim
