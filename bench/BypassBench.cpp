// BypassPlanner::lane_clear (issue 12): the robot's whole body swept along a clear 3.5 m bypass
// lane on a 240 x 240 costmap at 5 cm, for the campero (0.98 x 0.78 m, holonomic) and the
// pioneer3at (0.51 x 0.50 m, differential: its turns on the spot too), against the peer it
// replaced: the same lane walked at half a cell with only the centre's cell looked up. Every run
// checks the lane is clear first, so each call walks the whole lane.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "firmware/behavior/BypassPlanner.hpp"
#include "firmware/mapping/CostValues.hpp"

namespace {
using namespace carril::fw;

constexpr int kN = 240;
constexpr double kRes = 0.05;

// A 0.5 m-radius cylinder on the tape 2 m ahead, as lethal cells, and the lane round it.
struct Setup {
  RollingGrid<std::uint8_t> grid;
  BypassPlan plan;
  Setup(const Footprint& fp) {
    grid.init(kN, kN, kRes, cost::kFree);
    grid.recenter(2.0, 0.0);
    for (int cy = grid.origin_cy(); cy < grid.origin_cy() + kN; ++cy)
      for (int cx = grid.origin_cx(); cx < grid.origin_cx() + kN; ++cx)
        if (std::hypot(grid.center_of(cx) - 2.0, grid.center_of(cy)) <= 0.5)
          grid.at(cx, cy) = cost::kLethal;
    const double lane = 0.5 + 0.3 + fp.half_width_m, past = 2.5 + 0.3 + fp.half_length_m;
    plan.ok = true;
    plan.side = 1;
    plan.lateral = lane;
    plan.waypoints.push_back(Vec2(0.0, lane));
    plan.waypoints.push_back(Vec2(past, lane));
    plan.waypoints.push_back(Vec2(past + 0.15, 0.0));
  }
};

const Footprint kCampero{0.49, 0.39};
const Footprint kPioneer{0.254, 0.2485};

void body(benchmark::State& state, const Footprint& fp, bool holonomic) {
  const Setup s(fp);
  const BypassPlanner planner(AvoidConfig{}, fp, holonomic);
  if (!planner.lane_clear(s.plan, Pose2{}, 0, s.grid)) {
    std::fprintf(stderr, "bench_bypass: the lane should be clear\n");
    std::abort();
  }
  for (auto _ : state) benchmark::DoNotOptimize(planner.lane_clear(s.plan, Pose2{}, 0, s.grid));
}

// The peer: the centre's cell every half cell along the same legs.
bool centre_only(const BypassPlan& p, const RollingGrid<std::uint8_t>& g) {
  const double step = 0.5 * g.resolution();
  Vec2 a = Vec2::Zero();
  for (std::size_t i = 0; i < p.waypoints.size(); ++i) {
    const Vec2 b = p.waypoints[i];
    const int n = static_cast<int>(std::ceil((b - a).norm() / step));
    for (int k = 1; k <= n; ++k) {
      const Vec2 q = a + (b - a) * (double(k) / n);
      int cx = 0, cy = 0;
      if (!g.world_to_cell(q.x(), q.y(), cx, cy)) continue;
      const std::uint8_t c = g.at(cx, cy);
      if (c == cost::kInscribed || c == cost::kLethal) return false;
    }
    a = b;
  }
  return true;
}

void centre(benchmark::State& state, const Footprint& fp) {
  const Setup s(fp);
  for (auto _ : state) benchmark::DoNotOptimize(centre_only(s.plan, s.grid));
}

void BM_LaneBodyCampero(benchmark::State& st) {
  body(st, kCampero, true);
}
void BM_LaneBodyPioneer(benchmark::State& st) {
  body(st, kPioneer, false);
}
void BM_LaneCentreOnlyCampero(benchmark::State& st) {
  centre(st, kCampero);
}
BENCHMARK(BM_LaneBodyCampero)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LaneBodyPioneer)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LaneCentreOnlyCampero)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
