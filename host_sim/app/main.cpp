// carril_sim: runs one scenario in the Box2D simulator against the firmware, headless and as
// fast as it can go unless asked otherwise, and writes trajectory, summary and plots.
// Exit status: 0 the run met the scenario's expect block (or it has none), 1 it did not,
// 2 bad input or usage.
//
// Test hook: CARRIL_SIM_STARTUP_DELAY_MS=N sleeps N ms in start-up, after loading the scenario
// (interrupted by SIGINT/SIGTERM/SIGHUP), so that tests can signal a process still starting.
#include <CLI/CLI.hpp>
#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "host_sim/app/CostmapOutputs.hpp"
#include "host_sim/app/FpTraps.hpp"
#include "host_sim/app/HilMain.hpp"
#include "host_sim/app/LiveView.hpp"
#include "host_sim/app/SimRun.hpp"
#include "host_sim/output/RunOutputs.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"

namespace {
// The first stopping signal received (SIGINT, SIGTERM, SIGHUP), 0 for none.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
extern "C" void on_signal(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

// True (after saying so) when a signal came during start-up stage `stage`: nothing is written.
bool stopped_during_startup(const char* stage) {
  const int sig = g_signal.load();
  if (sig == 0) return false;
  std::fprintf(stderr, "carril_sim: stopped by %s during start-up (%s); nothing written\n",
               signal_name(sig), stage);
  return true;
}

// A non-negative decimal (--seed, as the scenario file's `seed`): digits only, an optional leading
// '+', at most 2^64 - 1.
std::optional<std::uint64_t> parse_decimal_u64(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  for (const char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

// The start-up delay test hook (see the top of this file); sleeps in slices so a signal ends it.
void startup_delay_for_tests() {
  const char* env = std::getenv("CARRIL_SIM_STARTUP_DELAY_MS");
  if (env == nullptr) return;
  const std::optional<std::uint64_t> ms = parse_decimal_u64(env);
  if (!ms) return;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(*ms);
  while (g_signal.load() == 0 && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}
// What the command line asks for.
struct Options {
  std::string scenario_path, out_dir;
  carril::sim::ScenarioOverrides overrides;
  std::optional<std::uint64_t> seed;  // the scenario's when absent
  bool realtime = false, view = false, quiet = false;
  bool plots = true;  // --no-plots clears it
  bool hil = false;   // --hil: the world for an external controller (HilMain.hpp)
  carril::sim::HilOptions hil_opt;
};

// Parses the command line into `o`. Returns the exit status when carril_sim should stop now
// (--help: 0, bad usage: 2), nothing to go on.
std::optional<int> parse_command_line(int argc, char** argv, Options& o) {
  CLI::App cli{"carril_sim: run a carril scenario in the Box2D host simulator"};
  std::string seed_text;
  cli.add_option("--scenario", o.scenario_path, "scenario file (YAML)")->required();
  cli.add_option("--out", o.out_dir,
                 "output directory (default runs/<scenario name>/, or "
                 "runs/<scenario name>_<preset>_<strategy>/ with --preset or --strategy)");
  cli.add_option("--preset", o.overrides.preset,
                 "robot preset instead of the scenario's (campero, create3, pioneer3at)");
  cli.add_option("--camera-noise", o.overrides.camera_noise,
                 "camera pixel noise std instead of the scenario's (robot.camera.noise_std)");
  cli.add_option("--strategy", o.overrides.strategy,
                 "mission strategy instead of the scenario's (marks, line_priority, pid)");
  // Taken as text and checked here: CLI11's integer conversion would wrap -1 to 2^64 - 1.
  auto* seed_opt =
      cli.add_option("--seed", seed_text,
                     "random seed, an integer in [0, 18446744073709551615] (default: the "
                     "scenario's seed)")
          ->expected(0, 1);  // a missing value ("--seed=", "--seed --quiet") is ours to report
  cli.add_flag("--realtime", o.realtime, "pace the run to wall-clock time");
  cli.add_flag("--view", o.view, "open a live window: top view and camera image");
  cli.add_flag("--quiet", o.quiet, "print only the final summary line");
  cli.add_flag("!--no-plots", o.plots,
               "write no images (trajectory, velocities, costmap and coverage PNGs), only the data "
               "files: campaigns run thousands of runs and replay the few worth a look");
  // Hardware in the loop (docs/hil.md).
  cli.add_flag("--hil", o.hil,
               "hardware in the loop: no firmware here; emulated CiA 402 drives on --can, the "
               "lidar over SCIP 2.0, camera and IMU in shared memory, in real time");
  cli.add_option("--can", o.hil_opt.can_iface, "SocketCAN interface of the drives (--hil)");
  cli.add_option("--controller", o.hil_opt.controller_path,
                 "the controller file carril_controller uses: drive node ids and units (--hil)");
  cli.add_option("--can-log", o.hil_opt.can_log,
                 "every CAN frame on the bus, in candump -l format (--hil)");
  cli.add_option("--scip-port", o.hil_opt.scip_port,
                 "TCP port of the SCIP 2.0 lidar on 127.0.0.1, 0 none (--hil; default 10940)");
  cli.add_option("--shm", o.hil_opt.shm,
                 "shared memory of camera and IMU, \"\" none (--hil; default /carril_sensors)");
  cli.add_option("--duration", o.hil_opt.duration_s,
                 "seconds to run instead of the scenario's duration_s (--hil)");
  cli.add_option("--inject", o.hil_opt.inject,
                 "T:DRIVE:WHAT, a fault for the emulated drives at T s (--hil; repeatable): "
                 "heartbeat_silence, bus_silence, refuse_enable, fault:0xCODE, corrupt:N, "
                 "unknown:N; DRIVE a wheel index or all");
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (o.hil && o.hil_opt.can_iface.empty()) {
    std::fprintf(stderr, "carril_sim: --hil needs --can IFACE\n");
    return 2;
  }
  if (!o.hil && (!o.hil_opt.can_iface.empty() || !o.hil_opt.inject.empty() ||
                 !o.hil_opt.can_log.empty() || !o.hil_opt.controller_path.empty())) {
    std::fprintf(stderr, "carril_sim: --can, --controller, --can-log and --inject need --hil\n");
    return 2;
  }
  if (seed_opt->count()) {
    o.seed = parse_decimal_u64(seed_text);
    if (!o.seed) {
      std::fprintf(stderr,
                   "carril_sim: --seed: expected an integer in [0, 18446744073709551615] (digits, "
                   "optionally a leading +), got \"%s\"\n",
                   seed_text.c_str());
      return 2;
    }
  }
  return std::nullopt;
}

// runs/<name>/, or runs/<name>_<preset>_<strategy>[_noise<std>]/ when the file is overridden.
std::string default_out_dir(const carril::sim::Scenario& s,
                            const carril::sim::ScenarioOverrides& overrides) {
  std::string dir = "runs/" + s.name;
  if (!overrides.empty()) dir += "_" + s.robot.preset + "_" + s.mission.strategy;
  if (!overrides.camera_noise.empty()) dir += "_noise" + overrides.camera_noise;
  return dir;
}

void print_log(carril::sim::SimRun& run, bool quiet) {
  for (const std::string& line : run.take_log()) {
    if (!quiet) std::printf("  %s\n", line.c_str());
  }
}

// Steps the run to its end (or a signal, or the view closing), printing its log and a progress
// line every 2 s of wall time. `t0` is when the run started.
void run_to_end(carril::sim::SimRun& run, const Options& o, carril::sim::LiveView* live,
                std::chrono::steady_clock::time_point t0) {
  using clock = std::chrono::steady_clock;
  const carril::sim::Scenario& scenario = run.scenario();
  const double period = 1.0 / scenario.robot.control_rate_hz;
  auto last_progress = t0;
  for (bool more = !run.finished(); more; more = run.step()) {
    print_log(run, o.quiet);
    if (g_signal.load() != 0) {
      run.abort();
      break;
    }
    const auto now = clock::now();
    if (o.realtime) {
      std::this_thread::sleep_until(t0 + std::chrono::duration<double>(run.sim_time_s()));
    }
    if (live && !live->update(run, period)) {
      run.abort();
      break;
    }
    if (!o.quiet && now - last_progress > std::chrono::seconds(2)) {
      last_progress = now;
      const double wall = std::chrono::duration<double>(now - t0).count();
      std::fprintf(stderr,
                   "  [%6.1f / %.0f s simulated, %5.1fx real time] state %s, progress %.2f\n",
                   run.sim_time_s(), scenario.duration_s, run.sim_time_s() / wall, run.state_name(),
                   run.progress());
    }
  }
  print_log(run, o.quiet);
}

void print_result(const carril::sim::Scenario& scenario, const carril::sim::RunSummary& summary,
                  const std::string& out_dir, bool plots) {
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
  std::printf("carril_sim: wrote %s/{trajectory.csv,summary.json%s}\n", out_dir.c_str(),
              plots ? ",trajectory.png,velocities.png" : "");
}
}  // namespace

int main(int argc, char** argv) {
  // First, so that a signal at any point of start-up is caught and reported, not fatal.
  install_signal_handlers();
  Options o;
  if (const std::optional<int> rc = parse_command_line(argc, argv, o)) return *rc;
  if (stopped_during_startup("reading the command line")) return 1;

  const carril::sim::LoadResult loaded =
      carril::sim::load_scenario(o.scenario_path, carril::sim::default_robots_dir(), o.overrides);
  if (!loaded.ok) {
    std::fprintf(stderr, "carril_sim: %s\n", loaded.error.c_str());
    return 2;
  }
  startup_delay_for_tests();
  if (stopped_during_startup("loading the scenario")) return 1;
  const carril::sim::Scenario& scenario = loaded.scenario;
  const std::uint64_t seed = o.seed.value_or(scenario.seed);
  const std::string out_dir =
      o.out_dir.empty() ? default_out_dir(scenario, o.overrides) : o.out_dir;
  // Before the run, not after it: a run whose outputs cannot be written is not started.
  if (std::string why; !carril::sim::prepare_output_dir(out_dir, why)) {
    std::fprintf(stderr, "carril_sim: --out: %s\n", why.c_str());
    return 2;
  }
  if (stopped_during_startup("checking the output directory")) return 1;

  if (o.hil) {
    return carril::sim::run_hil(scenario, seed, out_dir, o.hil_opt, g_signal);
  }

  std::unique_ptr<carril::sim::LiveView> live;
  if (o.view) {
    std::string why;
    live = carril::sim::LiveView::open(scenario, why);
    if (!live) {
      std::fprintf(stderr, "carril_sim: --view: %s\n", why.c_str());
      return 2;
    }
    if (stopped_during_startup("opening the view")) return 1;
  }

  // Floating-point traps on: a NaN born in the simulation stops it where it happens.
  carril::sim::enable_fp_traps();

  std::unique_ptr<carril::sim::SimRun> built;
  try {
    built = std::make_unique<carril::sim::SimRun>(scenario, seed);
  } catch (const std::invalid_argument& e) {
    // The configuration derived from the scenario, or the task table, is not valid.
    std::fprintf(stderr, "carril_sim: %s\n", e.what());
    return 2;
  }
  carril::sim::SimRun& run = *built;
  if (stopped_during_startup("building the world")) return 1;
  if (!o.quiet) {
    std::printf(
        "carril_sim: scenario %s (%s), robot %s, strategy %s, seed %llu, %.0f s simulated\n",
        scenario.name.c_str(), scenario.source_path.c_str(), scenario.robot.preset.c_str(),
        scenario.mission.strategy.c_str(), static_cast<unsigned long long>(seed),
        scenario.duration_s);
  }
  const auto t0 = std::chrono::steady_clock::now();
  // Start-up ends with the first tick; a signal after it stops the run, which is then written.
  run.step();
  if (stopped_during_startup("the first tick")) return 1;
  run_to_end(run, o, live.get(), t0);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const carril::sim::RunSummary summary = run.summary(wall);

  std::string error;
  const auto costmaps = [&run, &o](const std::string& dir, std::string& err) {
    if (o.plots && run.coverage() != nullptr && !run.coverage()->write_png(dir, err)) return false;
    return carril::sim::write_costmap_outputs(run.firmware(), dir, err, o.plots);
  };
  if (!carril::sim::write_run_outputs(out_dir, scenario, run.rows(), run.collisions(), summary,
                                      error, costmaps, o.plots)) {
    std::fprintf(stderr, "carril_sim: writing outputs: %s\n", error.c_str());
    return 2;
  }
  print_result(scenario, summary, out_dir, o.plots);
  return summary.passed ? 0 : 1;
}
