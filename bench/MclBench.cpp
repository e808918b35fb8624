// Monte Carlo localisation (issue 11): one update against its floor, resampling against the
// particle count, and the time of one step() for a particle budget.
//
// Map: the 10 x 8 m house of the tests (tests/unit/estimation/MclWorld.hpp) at 0.05 m. Scan: 360
// beams from a pose in the living room, 60 used.
//
// BM_MclUpdate: one whole update of 2000 particles (min = max = 2000, so KLD keeps the count):
// motion model, weighing, normalisation, mean and covariance, alias table, KLD count,
// low-variance resampling. The odometry goes 0.25 m forward and back on alternate iterations so
// every begin_update runs.
// BM_MclFloor: the same 2000 particles x 60 beams doing only what an update cannot avoid: per
// particle a sincos (the same fast_sincos), per beam the endpoint transform and the
// likelihood-field lookup, summed (LikelihoodField::sum_log_p, the localiser's own loop).
//
// BM_LowVarianceResample/N and BM_MclResampleStage/N: the low-variance pass alone (N weights to N
// particles, copies included) and the whole resampling stage the localiser runs (alias table,
// N i.i.d. KLD draws with their bins, low-variance pass), N = 1000 ... 16000.
// BM_AmclStyleResample/N: AMCL's pf_update_resample draw for comparison: each new particle picked
// by a linear search of the cumulative weights (quadratic).
//
// BM_MclUpdate/500..1000: the same at smaller counts (the largest whole update that fits a tick).
// BM_MclStep/B: a 2000-particle update spread over step(B) calls; counters give the longest step
// (per step index the median over updates, then the longest), the 99th percentile of all steps
// (preemptions on a shared machine included) and the steps per update.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "firmware/estimation/AliasSearch.hpp"
#include "firmware/estimation/BeamsThroughWalls.hpp"
#include "firmware/estimation/KldSampling.hpp"
#include "firmware/estimation/MclMath.hpp"
#include "firmware/estimation/MonteCarloLocalizer.hpp"
#include "firmware/estimation/Resampling.hpp"
#include "tests/unit/estimation/MclWorld.hpp"

namespace {

using namespace carril::fw;
namespace world = carril::test::mcl;

const Pose2 kMount{0.1, 0.0, 0.0};
const Pose2 kTruth{1.5, 3.5, 0.3};

struct World {
  OccupancyGrid map = world::make_house();
  carril::hal::LaserScan scan;
  World() {
    MclRng rng(1);
    world::synth_scan(map, kTruth, kMount, {}, rng, scan);
  }
};
const World& the_world() {
  static const World w;
  return w;
}

// Durations of the k-th step of each run [us], per k: per step index the median over runs (what
// the step costs, without the preemptions of a shared machine), and the longest of those: the
// tick budget the work needs.
double longest_median_step(std::vector<std::vector<double>>& by_step) {
  double longest = 0.0;
  for (std::vector<double>& v : by_step) {
    std::sort(v.begin(), v.end());
    longest = std::max(longest, v[v.size() / 2]);
  }
  return longest;
}

MclConfig update_config(int particles) {
  MclConfig c;
  c.max_particles = c.min_particles = particles;
  c.step_particles = particles;
  c.laser_max_range_m = 10.0;
  return c;
}

// A localiser tracking kTruth with `particles` particles, and the odometry for its next update.
struct Tracking {
  MonteCarloLocalizer mcl;
  bool forward = true;
  explicit Tracking(int particles) : mcl(update_config(particles), the_world().map) {
    mcl.set_pose(kTruth, 0.1, 0.05);
    mcl.update(the_world().scan, {}, kMount);
  }
  Pose2 next_odom() {
    forward = !forward;
    return forward ? Pose2{0.0, 0.0, 0.0} : Pose2{0.25, 0.0, 0.0};
  }
};

void BM_MclUpdate(benchmark::State& state) {
  Tracking t(int(state.range(0)));
  for (auto _ : state) {
    t.mcl.begin_update(the_world().scan, t.next_odom(), kMount);
    while (t.mcl.step(1 << 20)) {
    }
    benchmark::DoNotOptimize(t.mcl.estimate());
  }
  state.counters["particles"] = t.mcl.particle_count();
  state.counters["beams"] = t.mcl.telemetry().beams_used;
}
// 2000 against the floor; the smaller counts find the largest one whose whole update fits a tick.
BENCHMARK(BM_MclUpdate)->Arg(2000)->Arg(500)->Arg(750)->Arg(1000)->Unit(benchmark::kMicrosecond);

void BM_MclFloor(benchmark::State& state) {
  Tracking t(2000);
  const LikelihoodField& f = t.mcl.field();
  const std::vector<Particle> particles(t.mcl.particles(), t.mcl.particles() + 2000);
  // The same 60 beams the localiser picks: evenly spaced among the valid ones, in the robot
  // frame [cells].
  const auto& scan = the_world().scan;
  std::vector<int> valid;
  for (int i = 0; i < scan.count; ++i) {
    const float r = scan.ranges_m[std::size_t(i)];
    if (std::isfinite(r) && r >= scan.range_min_m && r < scan.range_max_m) valid.push_back(i);
  }
  const int nb = 60, nv = int(valid.size());
  std::vector<float> bx(nb), by(nb);
  const double inv_res = 1.0 / f.resolution();
  for (int k = 0; k < nb; ++k) {
    const int i = valid[std::size_t((2L * k + 1) * nv / (2L * nb))];
    const double a = scan.angle_min_rad + i * double(scan.angle_increment_rad);
    const double r = scan.ranges_m[std::size_t(i)];
    bx[std::size_t(k)] = float((kMount.x + r * std::cos(a)) * inv_res);
    by[std::size_t(k)] = float((kMount.y + r * std::sin(a)) * inv_res);
  }
  const double gx0 = 1.0 - f.origin_x() * inv_res, gy0 = 1.0 - f.origin_y() * inv_res;
  for (auto _ : state) {
    double total = 0.0;
    for (const Particle& p : particles) {
      double sd = 0.0, cd = 0.0;
      fast_sincos(p.yaw, sd, cd);
      const float c = float(cd), s = float(sd);
      const float gx = float(p.x * inv_res + gx0), gy = float(p.y * inv_res + gy0);
      total += f.sum_log_p(gx, gy, c, s, bx.data(), by.data(), nb);
    }
    benchmark::DoNotOptimize(total);
  }
}
BENCHMARK(BM_MclFloor)->Unit(benchmark::kMicrosecond);

// 16 sets of n weights exp(-8 u), taken in turn by successive iterations: a real filter has new
// weights every update, and one set reused would let the branch predictor learn the walk.
struct WeightSets {
  static constexpr int kSets = 16;
  std::vector<double> w[kSets];
  double total[kSets] = {};
  explicit WeightSets(int n) {
    MclRng rng(42);
    for (int k = 0; k < kSets; ++k) {
      w[k].resize(static_cast<std::size_t>(n));
      for (auto& x : w[k]) {
        x = std::exp(-8.0 * rng.uniform());
        total[k] += x;
      }
    }
  }
};

// The particle counts the resampling benchmarks sweep, N to N.
void resample_counts(benchmark::internal::Benchmark* b) {
  for (int n : {1000, 2000, 4000, 8000, 16000}) b->Arg(n);
}

// n particles spread over a 10 x 8 m floor, every heading.
std::vector<Particle> spread_particles(int n, MclRng& rng) {
  std::vector<Particle> out(static_cast<std::size_t>(n));
  for (auto& p : out) p = {rng.uniform(0, 10), rng.uniform(0, 8), rng.uniform(-kPi, kPi)};
  return out;
}

void BM_LowVarianceResample(benchmark::State& state) {
  const int n = int(state.range(0));
  const WeightSets ws(n);
  MclRng rng(1);
  const std::vector<Particle> in = spread_particles(n, rng);
  std::vector<Particle> out(in.size());
  LowVarianceResampler r;
  int set = 0;
  for (auto _ : state) {
    set = (set + 1) % WeightSets::kSets;
    r.begin(ws.w[set].data(), n, ws.total[set], n, rng.uniform());
    r.run(1 << 30, [&](int j, int i) { out[std::size_t(j)] = in[std::size_t(i)]; });
    benchmark::DoNotOptimize(out.data());
  }
  state.SetComplexityN(n);
}
BENCHMARK(BM_LowVarianceResample)
    ->Apply(resample_counts)
    ->Complexity(benchmark::oN)
    ->Unit(benchmark::kMicrosecond);

void BM_MclResampleStage(benchmark::State& state) {
  const int n = int(state.range(0));
  const WeightSets ws(n);
  MclRng rng(1);
  const std::vector<Particle> in = spread_particles(n, rng);
  std::vector<Particle> out(in.size());
  AliasTable alias(n);
  BinSet bins(n);
  LowVarianceResampler r;
  int set = 0;
  for (auto _ : state) {
    set = (set + 1) % WeightSets::kSets;
    const double* w = ws.w[set].data();
    const double total = ws.total[set];
    alias.begin(w, n, total);
    while (!alias.ready()) alias.build(1 << 30);
    bins.clear();
    for (int k = 0; k < n; ++k) {
      const Particle& p = in[std::size_t(alias.draw(rng))];
      bins.insert(int(std::floor(p.x / 0.5)), int(std::floor(p.y / 0.5)),
                  int(std::floor((p.yaw + kPi) / 0.1745)));
    }
    r.begin(w, n, total, n, rng.uniform());
    r.run(1 << 30, [&](int j, int i) { out[std::size_t(j)] = in[std::size_t(i)]; });
    benchmark::DoNotOptimize(out.data());
  }
  state.SetComplexityN(n);
}
BENCHMARK(BM_MclResampleStage)
    ->Apply(resample_counts)
    ->Complexity(benchmark::oN)
    ->Unit(benchmark::kMicrosecond);

void BM_AmclStyleResample(benchmark::State& state) {
  const int n = int(state.range(0));
  const WeightSets ws(n);
  std::vector<double> c(static_cast<std::size_t>(n) + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    c[std::size_t(i) + 1] = c[std::size_t(i)] + ws.w[0][std::size_t(i)] / ws.total[0];
  }
  const auto un = static_cast<std::size_t>(n);
  std::vector<Particle> in(un), out(un);
  MclRng rng(1);
  for (auto _ : state) {
    // pf_update_resample: for each new sample, r = drand48(), then
    // for (i = 0; i < count; i++) if (c[i] <= r && r < c[i+1]) break;
    for (int j = 0; j < n; ++j) {
      const double u = rng.uniform();
      int i = 0;
      for (; i < n; ++i) {
        if (c[std::size_t(i)] <= u && u < c[std::size_t(i) + 1]) break;
      }
      out[std::size_t(j)] = in[std::size_t(std::min(i, n - 1))];
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.SetComplexityN(n);
}
BENCHMARK(BM_AmclStyleResample)
    ->Apply(resample_counts)
    ->Complexity(benchmark::oNSquared)
    ->Unit(benchmark::kMillisecond);

void BM_MclStep(benchmark::State& state) {
  const int budget = int(state.range(0));
  Tracking t(2000);
  std::vector<std::vector<double>> by_step;  // durations of the k-th step of each update [us]
  std::vector<double> all;
  for (auto _ : state) {
    t.mcl.begin_update(the_world().scan, t.next_odom(), kMount);
    bool busy = true;
    for (std::size_t k = 0; busy; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      busy = t.mcl.step(budget);
      const double us =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
      if (by_step.size() <= k) by_step.emplace_back();
      by_step[k].push_back(us);
      all.push_back(us);
    }
  }
  std::sort(all.begin(), all.end());
  state.counters["longest_step_us"] = longest_median_step(by_step);
  state.counters["p99_step_us"] = all[std::size_t(0.99 * double(all.size() - 1))];
  state.counters["steps_per_update"] = double(by_step.size());
}
BENCHMARK(BM_MclStep)->Arg(100)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMicrosecond);

}  // namespace

// The kidnap reaction's costs (Localisation): scan_fit, a scan's fit at one pose, checked on
// every scan; set_global, the spread over the free space a loss of the fit starts (5000
// particles, the simulator's max_particles), once per loss.
void BM_MclScanFit(benchmark::State& state) {
  const World& w = the_world();
  MonteCarloLocalizer mcl(update_config(500), w.map);
  double sum = 0.0;
  for (auto _ : state) {
    sum += mcl.scan_fit(w.scan, kTruth, kMount);
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_MclScanFit)->Unit(benchmark::kMicrosecond);

// The walls check Localisation runs on every scan beside scan_fit: the same 60 returns walked
// through the map's cells (0.3 m margins), at the true pose (each walk stops short of its wall:
// every cell visited) and 1 m off (most walks end at the first wall they cross).
void BM_BeamsThroughWalls(benchmark::State& state) {
  const World& w = the_world();
  const Pose2 pose = state.range(0) == 0 ? kTruth : Pose2{kTruth.x + 1.0, kTruth.y, kTruth.yaw};
  long through = 0;
  for (auto _ : state) {
    through += beams_through_walls(w.map, w.scan, pose, kMount, 60, 12.0, 0.3).through;
    benchmark::DoNotOptimize(through);
  }
}
BENCHMARK(BM_BeamsThroughWalls)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_MclSetGlobal(benchmark::State& state) {
  const World& w = the_world();
  MclConfig c = update_config(int(state.range(0)));
  MonteCarloLocalizer mcl(c, w.map);
  for (auto _ : state) {
    mcl.set_global();
    benchmark::DoNotOptimize(mcl.estimate());
  }
}
BENCHMARK(BM_MclSetGlobal)->Arg(5000)->Unit(benchmark::kMicrosecond);

// The alias check of a regain (Localisation, AliasSearch): one scan scored at every candidate
// position of the house (0.1 m apart, 0.15 m from walls) at `headings` headings, the best 16
// refined. Counters: candidates, field lookups per microsecond of the whole search, and the
// longest step(20000) (Localisation's alias_lookups_per_tick), per step index the median over
// searches, then the longest.
void BM_AliasSearch(benchmark::State& state) {
  const World& w = the_world();
  MonteCarloLocalizer mcl(update_config(500), w.map);
  AliasSearchConfig c;
  c.headings = int(state.range(0));
  c.max_range_m = 10.0;
  AliasSearch search(c, mcl.field(), w.map);
  constexpr long kLookups = 20000;
  std::vector<std::vector<double>> step_us;
  long lookups = 0;
  for (auto _ : state) {
    search.begin(w.scan, kTruth, kMount);
    std::size_t k = 0;
    for (bool more = true; more; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      more = search.step(kLookups);
      const auto t1 = std::chrono::steady_clock::now();
      if (step_us.size() <= k) step_us.emplace_back();
      step_us[k].push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    lookups += long(search.candidate_count()) * c.headings * c.coarse_beams;
    benchmark::DoNotOptimize(search.result());
  }
  state.counters["candidates"] = double(search.candidate_count());
  state.counters["steps"] = double(step_us.size());
  state.counters["longest_step_us"] = longest_median_step(step_us);
  state.counters["lookups_per_us"] =
      benchmark::Counter(double(lookups) * 1e-6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AliasSearch)->Arg(1)->Arg(4)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
