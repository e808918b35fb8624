// The wavefront planner against Boost.Graph's dijkstra_shortest_paths (issue 10 item 10).
//
// Both search the same 1000 x 1000 8-connected grid with 20 % obstacles (random discs, seeded)
// and graded costs on 30 % of the free cells, from the goal at the centre over everything
// reachable, with the same float edge weights (WavefrontPlanner::step_weight: the cost of a step
// into a cell), the same corner rule and the same float distances.
//
// Boost gets its fastest static graph, a compressed_sparse_row_graph built once outside the
// timed loop, and the standard dijkstra_shortest_paths call (4-ary indirect heap, two-bit colour
// map); its distance and predecessor vectors are allocated once outside too. Timed per
// iteration: carril's start() (copy of the cost grid + reset of the field) + step() to the end;
// Boost's call (which initialises its own maps). Before timing, both fields are compared cell by
// cell and the start -> goal costs are printed.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/planning/WavefrontPlanner.hpp"

namespace {

using carril::fw::GridCell;
using carril::fw::WavefrontConfig;
using carril::fw::WavefrontPlanner;
using carril::fw::WavefrontStatus;
namespace cost = carril::fw::cost;

constexpr int kN = 1000;
constexpr int kGoalX = kN / 2, kGoalY = kN / 2;
constexpr int kStartX = 2, kStartY = 2;

struct EdgeWeight {
  float w;
};
using CsrGraph =
    boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeWeight>;

struct Fixture {
  std::vector<std::uint8_t> costs;
  WavefrontConfig cfg;
  WavefrontPlanner planner;
  std::unique_ptr<CsrGraph> graph;
  std::vector<float> boost_dist;
  std::vector<std::uint32_t> boost_pred;
  std::size_t edges = 0;

  Fixture() {
    costs.assign(std::size_t(kN) * kN, cost::kFree);
    std::mt19937 rng(20261123);
    std::uniform_int_distribution<int> pos(0, kN - 1), radius(2, 12), graded(1, 252);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t lethal = 0;
    while (double(lethal) < 0.2 * kN * kN) {
      const int cx = pos(rng), cy = pos(rng), r = radius(rng);
      for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) {
          if (x < 0 || y < 0 || x >= kN || y >= kN ||
              (x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r)
            continue;
          auto& c = costs[std::size_t(y) * kN + std::size_t(x)];
          if (c != cost::kLethal) {
            c = cost::kLethal;
            ++lethal;
          }
        }
    }
    for (auto& c : costs)
      if (c == cost::kFree && u(rng) < 0.3) c = std::uint8_t(graded(rng));
    for (int y = -2; y <= 2; ++y)
      for (int x = -2; x <= 2; ++x) {
        costs[std::size_t(kGoalY + y) * kN + std::size_t(kGoalX + x)] = cost::kFree;
        costs[std::size_t(kStartY + y) * kN + std::size_t(kStartX + x)] = cost::kFree;
      }
    cfg.cost_weight = 3.0;
    planner.init(kN, kN, cfg);
    build_graph();
    boost_dist.assign(costs.size(), 0.0f);
    boost_pred.assign(costs.size(), 0);
  }

  bool open(int x, int y) const {
    return x >= 0 && y >= 0 && x < kN && y < kN &&
           cost::passable(costs[std::size_t(y) * kN + std::size_t(x)]);
  }

  // The reversed robot graph, as the wavefront searches it: an edge v -> u for each allowed
  // robot step u -> v, weighted by the step into v.
  void build_graph() {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> list;
    std::vector<EdgeWeight> weights;
    list.reserve(std::size_t(kN) * kN * 7);
    weights.reserve(list.capacity());
    const int dx[8] = {1, 0, -1, 0, 1, -1, -1, 1}, dy[8] = {0, 1, 0, -1, 1, 1, -1, -1};
    for (int vy = 0; vy < kN; ++vy)
      for (int vx = 0; vx < kN; ++vx) {
        if (!open(vx, vy)) continue;
        const std::uint8_t c = costs[std::size_t(vy) * kN + std::size_t(vx)];
        for (int k = 0; k < 8; ++k) {
          const int ux = vx + dx[k], uy = vy + dy[k];
          if (!open(ux, uy)) continue;
          if (k >= 4 && !open(ux, vy) && !open(vx, uy)) continue;  // between two walls
          list.emplace_back(std::uint32_t(vy * kN + vx), std::uint32_t(uy * kN + ux));
          weights.push_back({planner.step_weight(c, k >= 4)});
        }
      }
    edges = list.size();
    graph = std::make_unique<CsrGraph>(boost::edges_are_sorted, list.begin(), list.end(),
                                       weights.begin(), std::size_t(kN) * kN);
  }

  void run_carril() {
    planner.start(costs.data(), kN, kN, kGoalX, kGoalY);
    planner.step(0xFFFFFFFFu);
  }
  void run_boost() {
    const auto goal = std::uint32_t(kGoalY * kN + kGoalX);
    const auto index = boost::get(boost::vertex_index, *graph);
    boost::dijkstra_shortest_paths(
        *graph, goal,
        boost::weight_map(boost::get(&EdgeWeight::w, *graph))
            .distance_map(boost::make_iterator_property_map(boost_dist.begin(), index))
            .predecessor_map(boost::make_iterator_property_map(boost_pred.begin(), index))
            .distance_inf(std::numeric_limits<float>::infinity()));
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void check_once() {
  static bool done = false;
  if (done) return;
  done = true;
  Fixture& f = fixture();
  f.run_carril();
  f.run_boost();
  std::size_t reachable = 0, mismatched = 0;
  double max_rel = 0.0;
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const float b = f.boost_dist[std::size_t(y) * kN + std::size_t(x)];
      const bool breach = std::isfinite(b);
      if (breach != f.planner.reachable(x, y)) {
        ++mismatched;
        continue;
      }
      if (!breach) continue;
      ++reachable;
      const double rel = std::fabs(double(f.planner.cost_to_goal(x, y)) - double(b)) / (1.0 + b);
      if (rel > max_rel) max_rel = rel;
    }
  static carril::fw::StaticVector<GridCell, 8192> path;
  const auto r = f.planner.extract_path(kStartX, kStartY, path);
  std::printf(
      "grid %d x %d, %.1f %% lethal, %zu edges; reachable %zu, reachability mismatches %zu, "
      "max relative field difference %.3g\n",
      kN, kN, 100.0 * double(std::count(f.costs.begin(), f.costs.end(), cost::kLethal)) / (kN * kN),
      f.edges, reachable, mismatched, max_rel);
  std::printf(
      "start (%d,%d) -> goal (%d,%d): carril cost %.6f, boost cost %.6f, path %s, %zu cells\n",
      kStartX, kStartY, kGoalX, kGoalY, double(f.planner.cost_to_goal(kStartX, kStartY)),
      double(f.boost_dist[std::size_t(kStartY) * kN + kStartX]), carril::fw::to_string(r),
      path.size());
}

void BM_CarrilWavefront(benchmark::State& state) {
  check_once();
  Fixture& f = fixture();
  for (auto _ : state) {
    f.run_carril();
    benchmark::DoNotOptimize(f.planner.cost_to_goal(kStartX, kStartY));
  }
  state.counters["expanded"] = double(f.planner.expanded());
}
BENCHMARK(BM_CarrilWavefront)->Unit(benchmark::kMillisecond);

void BM_BoostDijkstraCsr(benchmark::State& state) {
  check_once();
  Fixture& f = fixture();
  for (auto _ : state) {
    f.run_boost();
    benchmark::DoNotOptimize(f.boost_dist[std::size_t(kStartY) * kN + kStartX]);
  }
}
BENCHMARK(BM_BoostDijkstraCsr)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
