// carril_sim: runs one scenario in the Box2D simulator against the firmware, headless and as
// fast as it can go unless asked otherwise, and writes trajectory, summary and plots.
// Exit status: 0 the run met the scenario's expect block (or it has none), 1 it did not,
// 2 bad input or usage.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <thread>

#include "host_sim/app/LiveView.hpp"
#include "host_sim/app/SimRun.hpp"
#include "host_sim/output/RunOutputs.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"
#include "tests/support/FpTraps.hpp"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) {
  g_stop.store(true);
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"carril_sim: run a carril scenario in the Box2D host simulator"};
  std::string scenario_path, out_dir;
  carril::sim::ScenarioOverrides overrides;
  std::uint64_t seed = 0;
  bool realtime = false, view = false, quiet = false;
  cli.add_option("--scenario", scenario_path, "scenario file (YAML)")->required();
  cli.add_option("--out", out_dir,
                 "output directory (default runs/<scenario name>/, or "
                 "runs/<scenario name>_<preset>_<strategy>/ with --preset or --strategy)");
  cli.add_option("--preset", overrides.preset,
                 "robot preset instead of the scenario's (campero, pioneer3at)");
  cli.add_option("--strategy", overrides.strategy,
                 "mission strategy instead of the scenario's (marks, line_priority, pid)");
  auto* seed_opt = cli.add_option("--seed", seed, "random seed (default: the scenario's seed)");
  cli.add_flag("--realtime", realtime, "pace the run to wall-clock time");
  cli.add_flag("--view", view, "open a live window: top view and camera image");
  cli.add_flag("--quiet", quiet, "print only the final summary line");
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : 2;
  }

  const carril::sim::LoadResult loaded =
      carril::sim::load_scenario(scenario_path, carril::sim::default_robots_dir(), overrides);
  if (!loaded.ok) {
    std::fprintf(stderr, "carril_sim: %s\n", loaded.error.c_str());
    return 2;
  }
  const carril::sim::Scenario& scenario = loaded.scenario;
  if (!seed_opt->count()) seed = scenario.seed;
  if (out_dir.empty()) {
    out_dir = "runs/" + scenario.name;
    if (!overrides.empty()) {
      out_dir += "_" + scenario.robot.preset + "_" + scenario.mission.strategy;
    }
  }

  std::unique_ptr<carril::sim::LiveView> live;
  if (view) {
    std::string why;
    live = carril::sim::LiveView::open(scenario, why);
    if (!live) {
      std::fprintf(stderr, "carril_sim: --view: %s\n", why.c_str());
      return 2;
    }
  }

  // Floating-point traps on: a NaN born in the simulation stops it where it happens.
  carril::test::enable_fp_traps();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  carril::sim::SimRun run(scenario, seed);
  if (!quiet) {
    std::printf(
        "carril_sim: scenario %s (%s), robot %s, strategy %s, seed %llu, %.0f s simulated\n",
        scenario.name.c_str(), scenario.source_path.c_str(), scenario.robot.preset.c_str(),
        scenario.mission.strategy.c_str(), static_cast<unsigned long long>(seed),
        scenario.duration_s);
  }
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  auto last_progress = t0;
  const double period = 1.0 / scenario.robot.control_rate_hz;
  while (run.step()) {
    for (const std::string& line : run.take_log()) {
      if (!quiet) std::printf("  %s\n", line.c_str());
    }
    if (g_stop.load()) {
      run.abort();
      break;
    }
    const auto now = clock::now();
    if (realtime) {
      std::this_thread::sleep_until(t0 + std::chrono::duration<double>(run.sim_time_s()));
    }
    if (live && !live->update(run, period)) {
      run.abort();
      break;
    }
    if (!quiet && now - last_progress > std::chrono::seconds(2)) {
      last_progress = now;
      const double wall = std::chrono::duration<double>(now - t0).count();
      std::fprintf(stderr,
                   "  [%6.1f / %.0f s simulated, %5.1fx real time] state %s, progress %.2f\n",
                   run.sim_time_s(), scenario.duration_s, run.sim_time_s() / wall, run.state_name(),
                   run.progress());
    }
  }
  for (const std::string& line : run.take_log()) {
    if (!quiet) std::printf("  %s\n", line.c_str());
  }
  const double wall = std::chrono::duration<double>(clock::now() - t0).count();
  const carril::sim::RunSummary summary = run.summary(wall);

  std::string error;
  if (!carril::sim::write_run_outputs(out_dir, scenario, run.rows(), run.collisions(), summary,
                                      error)) {
    std::fprintf(stderr, "carril_sim: writing outputs: %s\n", error.c_str());
    return 2;
  }
  std::printf(
      "carril_sim: %s: %s, %s after %.1f s simulated in %.2f s wall (%.0fx real time); progress "
      "%.3f, "
      "laps %d, collisions %d, cross-track rms %.4f m, max %.4f m, tick p99 %.1f us, heap "
      "allocations in ticks %ld\n",
      scenario.name.c_str(), summary.passed ? "PASSED" : "FAILED", summary.result.c_str(),
      summary.sim_time_s, summary.wall_time_s, summary.real_time_factor, summary.progress,
      summary.laps, summary.collisions, summary.cross_track_rms_m, summary.cross_track_max_m,
      summary.tick_compute_p99_us, summary.heap_allocations_after_init);
  for (const std::string& u : summary.unmet_expectations) std::printf("  unmet: %s\n", u.c_str());
  std::printf("carril_sim: wrote %s/{trajectory.csv,summary.json,trajectory.png,velocities.png}\n",
              out_dir.c_str());
  return summary.passed ? 0 : 1;
}
