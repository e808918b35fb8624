// carril_robot: the firmware on the robot computer. Wires the robot (RobotTopology), runs the
// firmware at its configured rate on absolute deadlines and, when it stops, prints the firmware's
// telemetry once.
// Its configuration comes from the robot description, mission and (optional) tuning files given on
// the command line, through the same loader as the simulator's (loader/).
// Exit status: 0 it ran the requested ticks (or until SIGINT/SIGTERM when no --ticks was given),
// 1 a signal stopped it before the requested ticks, 2 bad usage or configuration, 3 the drives
// did not come up.
#include <pthread.h>
#include <sched.h>
#include <Eigen/Core>

#include <atomic>
#include <charconv>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

#include "firmware/app/EventFormat.hpp"
#include "loader/FirmwareConfigBuilder.hpp"
#include "loader/MissionLoader.hpp"
#include "loader/RobotLoader.hpp"
#include "loader/TuningLoader.hpp"
#include "targets/robot/RobotTopology.hpp"

namespace {

using carril::fw::Controller;
using carril::fw::Event;
using carril::fw::FirmwareTelemetry;
using carril::fw::LoopStats;

// Set by the signal handler, read by the loop's step function.
std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_signal(int) {
  g_stop.store(true, std::memory_order_relaxed);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

constexpr const char* kUsage =
    "usage: carril_robot --robot FILE --mission FILE [--tuning FILE] [--ticks N]\n"
    "  Runs the line-following firmware on the robot at its control rate.\n"
    "  --robot FILE    the robot description (config/robots/<name>.yaml)\n"
    "  --mission FILE  the mission (config/missions/<name>.yaml)\n"
    "  --tuning FILE   component tuning (config/tuning/<name>.yaml); default: none\n"
    "  --ticks N       stop after N control ticks (N >= 1); default: run until SIGINT or SIGTERM\n"
    "  --help          print this and exit\n"
    "Prints the firmware telemetry when it stops.\n"
    "Exit status: 0 ran the requested ticks (or until a signal, without --ticks),\n"
    "1 a signal stopped it before the requested ticks, 2 bad usage or configuration\n"
    "(the message names the file and the key), 3 the drives did not come up.\n";

struct Options {
  const char* robot = nullptr;    // --robot FILE
  const char* mission = nullptr;  // --mission FILE
  const char* tuning = nullptr;   // --tuning FILE (optional)
  std::uint64_t ticks = 0;        // 0: until a signal
  bool help = false;
};

struct UsageError {
  const char* why = "";
  const char* arg = "";  // the offending argument
};

// Plain argv parsing (no CLI library on the target). Returns false with the reason in `err`.
bool parse_args(int argc, char** argv, Options& opt, UsageError& err) {
  struct Valued {
    const char* name;
    const char** file;  // a file option's value, or nullptr for --ticks
  };
  const Valued options[] = {
      {"--robot", &opt.robot},
      {"--mission", &opt.mission},
      {"--tuning", &opt.tuning},
      {"--ticks", nullptr},
  };
  bool have_ticks = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    err.arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      opt.help = true;
      return true;
    }
    const Valued* which = nullptr;
    const char* value = nullptr;
    for (const Valued& o : options) {
      const std::string_view name = o.name;
      if (arg == name) {
        if (i + 1 >= argc) {
          err.why = "option needs a value";
          return false;
        }
        which = &o;
        value = argv[++i];
      } else if (arg.size() > name.size() && arg.starts_with(name) && arg[name.size()] == '=') {
        which = &o;
        value = argv[i] + name.size() + 1;
      }
      if (which != nullptr) break;
    }
    if (which == nullptr) {
      err.why = "unknown argument";
      return false;
    }
    err.arg = value;
    if (which->file != nullptr) {
      if (*which->file != nullptr) {
        err.why = "option given more than once";
        err.arg = which->name;
        return false;
      }
      if (value[0] == '\0') {
        err.why = "option needs a file name";
        err.arg = which->name;
        return false;
      }
      *which->file = value;
      continue;
    }
    if (have_ticks) {
      err.why = "--ticks given more than once";
      return false;
    }
    have_ticks = true;
    const std::string_view v = value;
    std::uint64_t n = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (v.empty() || ec != std::errc{} || end != v.data() + v.size() || n == 0) {
      err.why = "--ticks needs a whole number of ticks >= 1";
      return false;
    }
    opt.ticks = n;
  }
  if (opt.robot == nullptr || opt.mission == nullptr) {
    err.why = "missing required option";
    err.arg = opt.robot == nullptr ? "--robot" : "--mission";
    return false;
  }
  return true;
}

// The firmware configuration from the files on the command line, built by the same loader as
// the simulator's. Prints the reason (file and key) and returns false when a file is missing or
// wrong.
bool load_config(const Options& opt, carril::loader::RobotSpec& robot,
                 carril::loader::MissionSpec& mission, carril::fw::FirmwareConfig& out) {
  std::string error;
  if (!carril::loader::load_robot_preset(opt.robot, robot, error)) {
    std::fprintf(stderr, "carril_robot: --robot: %s\n", error.c_str());
    return false;
  }
  if (!carril::loader::load_mission(opt.mission, robot, mission, error)) {
    std::fprintf(stderr, "carril_robot: --mission: %s\n", error.c_str());
    return false;
  }
  carril::loader::Tuning tuning;
  if (opt.tuning != nullptr && !carril::loader::load_tuning(opt.tuning, tuning, error)) {
    std::fprintf(stderr, "carril_robot: --tuning: %s\n", error.c_str());
    return false;
  }
  const carril::loader::BuildResult built = carril::loader::build_firmware_config(
      robot, mission, opt.tuning != nullptr ? &tuning : nullptr);
  if (!built.ok) {
    std::fprintf(stderr, "carril_robot: configuration: %s\n", built.error.c_str());
    return false;
  }
  out = built.config;
  return true;
}

void print_telemetry(const FirmwareTelemetry& all, const LoopStats& loop) {
  const carril::fw::ControllerTelemetry& t = all.controller;
  std::printf("telemetry:\n");
  std::printf("  ticks %llu\n", static_cast<unsigned long long>(t.ticks));
  std::printf(
      "  tick compute: p50 %.2f us, p99 %.2f us, max %.2f us (budget %.0f us), overruns %llu\n",
      t.tick_p50_us, t.tick_p99_us, t.tick_max_us, t.tick_budget_us,
      static_cast<unsigned long long>(t.tick_overruns));
  std::printf("  loop: periods %llu, missed deadlines %llu\n",
              static_cast<unsigned long long>(loop.periods),
              static_cast<unsigned long long>(loop.missed_deadlines));
  std::printf("  %-12s %7s %6s %8s %8s %9s %9s\n", "task", "divisor", "offset", "runs", "overruns",
              "p99 us", "max us");
  for (const auto& task : t.tasks) {
    std::printf("  %-12s %7u %6u %8llu %8llu %9.2f %9.2f\n", task.name, task.divisor, task.offset,
                static_cast<unsigned long long>(task.runs),
                static_cast<unsigned long long>(task.overruns), task.p99_us, task.max_us);
  }
  std::printf("  events dropped %llu\n", static_cast<unsigned long long>(t.events_dropped));
  std::printf(
      "  components: odometry %llu updates, %.2f m; camera frames %llu, scans %llu; motion %llu "
      "commands, %llu with drives not ready, %llu quick stops\n",
      static_cast<unsigned long long>(all.odometry.updates), all.odometry.distance_m,
      static_cast<unsigned long long>(all.watch.camera_frames),
      static_cast<unsigned long long>(all.watch.scans),
      static_cast<unsigned long long>(all.output.commands),
      static_cast<unsigned long long>(all.output.drives_not_ready),
      static_cast<unsigned long long>(all.output.quick_stops));
  std::printf("  mission %s: %s, state %s, phase %s\n", all.mission,
              carril::fw::mission_status_name(t.status), t.state, t.phase);
  std::printf("  state %s, fault %s\n", t.state, carril::fw::fault_name(t.fault));
}

// The slow rate group's cycles, tasks and events (its thread has stopped).
void print_slow_group(carril::robot::RobotTopology& topo) {
  const carril::fw::SlowCycleCounters c = topo.slow.cycle_counters();
  std::printf(
      "slow rate group: %.0f Hz, cycles %llu (thread %llu, missed deadlines %llu), "
      "p99 %.0f us, max %.0f us\n",
      c.rate_hz, static_cast<unsigned long long>(c.cycles),
      static_cast<unsigned long long>(topo.slow_thread.cycles()),
      static_cast<unsigned long long>(topo.slow_thread.missed_deadlines()), c.p99_us, c.max_us);
  for (std::size_t i = 0; i < topo.slow.size(); ++i) {
    const carril::fw::TaskCounters t = topo.slow.counters(i);
    std::printf("  %-12s %5.1f Hz %8llu runs %8llu overruns\n", t.name, t.rate_hz,
                static_cast<unsigned long long>(t.runs),
                static_cast<unsigned long long>(t.overruns));
  }
  std::printf("  status lines written %llu\n",
              static_cast<unsigned long long>(topo.reporter.lines()));
  Event e;
  while (topo.slow_events.pop(e)) {
    char line[160];
    carril::fw::format_event(e, double(e.t_ns) * 1e-9, line, sizeof line);
    std::printf("  %s\n", line);
  }
}

// State changes and faults, oldest first (the controller keeps the newest kEventLog).
void print_events(Controller& ctl, carril::hal::TimeNs t0_ns) {
  std::printf("events (newest %zu kept):\n", Controller::kEventLog);
  Event e;
  while (ctl.events().pop(e)) {
    const double t = double(e.t_ns - t0_ns) * 1e-9;
    char line[160];
    carril::fw::format_event(e, t, line, sizeof line);
    std::printf("  %s\n", line);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  UsageError err;
  if (!parse_args(argc, argv, opt, err)) {
    std::fprintf(stderr, "carril_robot: %s: '%s'\n%s", err.why, err.arg, kUsage);
    return 2;
  }
  if (opt.help) {
    std::fputs(kUsage, stdout);
    return 0;
  }

  // Init: everything is read, created and wired here, before the first tick; nothing after this
  // allocates.
  install_signal_handlers();
  carril::loader::RobotSpec robot;
  carril::loader::MissionSpec mission;
  carril::fw::FirmwareConfig config;
  if (!load_config(opt, robot, mission, config)) return 2;
  carril::fw::Status status;
  const auto topo = carril::robot::RobotTopology::create(config, status);
  if (!topo) {
    std::fprintf(stderr, "carril_robot: configuration: %s\n", status.message());
    return 2;
  }
  const carril::fw::FirmwareConfig& cfg = topo->config;
  std::printf("carril_robot: robot %s (%s), mission %s %s (%s)\n", robot.preset.c_str(), opt.robot,
              mission.type.c_str(), mission.strategy.c_str(), opt.mission);
  std::printf(
      "carril_robot: %s, wheel radius %.3f m, wheelbase %.2f m, track %.2f m, camera %dx%d, "
      "%.0f Hz; lidar %s, imu %s\n",
      cfg.drive.type == carril::fw::DriveType::Mecanum ? "mecanum" : "differential",
      cfg.drive.wheel_radius_m, cfg.drive.wheelbase_m, cfg.drive.track_m, cfg.camera.camera.width,
      cfg.camera.camera.height, cfg.rate_hz, cfg.lidar.present ? "fitted" : "not fitted",
      cfg.watch.imu_present ? "fitted" : "not fitted");
  std::printf("carril_robot: devices: null camera, lidar, imu and %d drives (no CAN backend yet)\n",
              topo->drives.count());
  // Drive bring-up (on a bus: boot-up, configuration) happens once, before the first tick.
  const carril::hal::DriveInitResult up = topo->drives.init();
  if (!up.ok) {
    std::fprintf(stderr, "carril_robot: drives did not come up: %s\n", up.what);
    return 3;
  }
  if (opt.ticks > 0) {
    std::printf("carril_robot: running %llu ticks\n", static_cast<unsigned long long>(opt.ticks));
  } else {
    std::printf("carril_robot: running until SIGINT or SIGTERM\n");
  }
  std::fflush(stdout);

  // Priorities: the control loop above the slow rate group, so heavy work never delays a tick.
  // Without real-time privileges both run as ordinary threads, and that is said.
  sched_param loop_param{};
  loop_param.sched_priority = carril::robot::kLoopPriority;
  const bool loop_fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &loop_param) == 0;
  if (!topo->start_slow_group(loop_fifo)) {
    std::fprintf(stderr, "carril_robot: slow rate group: %s\n", topo->slow_thread.note());
    return 2;
  }
  std::printf("carril_robot: control loop %s, slow rate group %s%s%s\n",
              loop_fifo ? "SCHED_FIFO 50" : "SCHED_OTHER (no real-time privileges)",
              topo->slow_thread.policy() == carril::hal::PeriodicThread::Policy::Fifo
                  ? "SCHED_FIFO 10"
                  : "SCHED_OTHER",
              *topo->slow_thread.note() ? ": " : "", topo->slow_thread.note());
  std::fflush(stdout);

  // The loop: one firmware step per period. A signal ends it at the next period (the sleep
  // restarts after the handler, so that is at most one period later).
  const carril::hal::TimeNs t0_ns = topo->clock.now_ns();
  const LoopStats loop = topo->loop.run(
      [&app = topo->app] {
        if (g_stop.load(std::memory_order_relaxed)) return false;
        // The firmware's tick touches no heap; Eigen checks that where asserts are on.
        Eigen::internal::set_is_malloc_allowed(false);
        app.step();
        Eigen::internal::set_is_malloc_allowed(true);
        return true;
      },
      opt.ticks);

  // Stopped: the slow group first (its thread reads what the loop published), then report once.
  topo->slow_thread.stop();
  topo->firmware.refresh_telemetry();
  const FirmwareTelemetry& all = topo->firmware.telemetry();
  const carril::fw::ControllerTelemetry& tel = all.controller;
  const bool interrupted = opt.ticks > 0 && tel.ticks < opt.ticks;
  if (interrupted) {
    std::printf("carril_robot: stopped by a signal after %llu of %llu ticks\n",
                static_cast<unsigned long long>(tel.ticks),
                static_cast<unsigned long long>(opt.ticks));
  } else if (opt.ticks > 0) {
    std::printf("carril_robot: ran the requested %llu ticks\n",
                static_cast<unsigned long long>(opt.ticks));
  } else {
    std::printf("carril_robot: stopped by a signal after %llu ticks\n",
                static_cast<unsigned long long>(tel.ticks));
  }
  print_telemetry(all, loop);
  print_slow_group(*topo);
  print_events(topo->firmware.controller, t0_ns);
  return interrupted ? 1 : 0;
}
