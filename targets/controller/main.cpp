// carril_controller: the firmware on the robot's Linux computer. Opens the CAN bus and the sensor
// links the controller file names, brings the CiA 402 drives up, wires the firmware
// (ControllerTopology), runs it at its configured rate on CLOCK_MONOTONIC absolute deadlines
// (SCHED_FIFO and mlockall when configured and permitted) and, when it stops, quick-stops the
// drives, sends NMT stop and prints the firmware's telemetry and the loop's latency figures
// (also on SIGUSR1, while running).
// Its configuration comes from the robot description, controller, mission and (optional) tuning
// files given on the command line, through the same loader as the simulator's (loader/).
// Exit status: 0 it ran the requested ticks (or until SIGINT, SIGTERM or SIGHUP when no --ticks was
// given; SIGPIPE is ignored),
// 1 a signal stopped it before the requested ticks, 2 bad usage or configuration (or a CAN
// interface or sensor link that cannot be opened), 3 the drives did not come up.
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <Eigen/Core>

#include <atomic>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

#include "firmware/app/EventFormat.hpp"
#include "hal/canopen/Frames.hpp"
#include "targets/controller/ControllerConfig.hpp"
#include "targets/controller/ControllerTopology.hpp"

namespace {

using carril::fw::Controller;
using carril::fw::Event;
using carril::fw::FirmwareTelemetry;
using carril::fw::LoopStats;

// Set by the signal handlers, read by the loop's step function.
std::atomic<bool> g_stop{false};
std::atomic<bool> g_report{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

// The first stopping signal received (SIGINT, SIGTERM, SIGHUP), 0 for none: named in the report.
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free int");

extern "C" void on_signal(int sig) {
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, sig, std::memory_order_relaxed);
  g_stop.store(true, std::memory_order_relaxed);
}
extern "C" void on_report(int) {
  g_report.store(true, std::memory_order_relaxed);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  // A hang-up (the terminal or the ssh session that started it closed) stops the robot as a
  // SIGTERM does: quick stop, NMT stop, the report; it must not kill the process with the
  // wheels still commanded.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  // A closed stdout or stderr (a pipe whose reader went away) must never kill the controller:
  // writes then fail with EPIPE, and the report's lines are lost, not the stop.
  struct sigaction ign {};
  ign.sa_handler = SIG_IGN;
  sigemptyset(&ign.sa_mask);
  sigaction(SIGPIPE, &ign, nullptr);
  struct sigaction sr {};
  sr.sa_handler = on_report;
  sigemptyset(&sr.sa_mask);
  sr.sa_flags = SA_RESTART;
  sigaction(SIGUSR1, &sr, nullptr);
}

constexpr const char* kUsage =
    "usage: carril_controller --robot FILE --controller FILE --mission FILE [--tuning FILE]\n"
    "                         [--ticks N] [--can-log FILE]\n"
    "  Runs the line-following firmware on the robot at its control rate, driving CiA 402\n"
    "  wheel drives over SocketCAN.\n"
    "  --robot FILE       the robot description (config/robots/<name>.yaml)\n"
    "  --controller FILE  CAN bus, drives, sensor sources, loop (config/controller/<name>.yaml)\n"
    "  --mission FILE     the mission (config/missions/<name>.yaml)\n"
    "  --tuning FILE      component tuning (config/tuning/<name>.yaml); default: none\n"
    "  --ticks N          stop after N control ticks (N >= 1); default: until a stopping signal\n"
    "  --can-log FILE     every CAN frame sent and received, in candump -l format\n"
    "  --help             print this and exit\n"
    "SIGUSR1 prints the loop's wake latency and compute figures; SIGINT or SIGTERM stop it\n"
    "(quick stop, then NMT stop). Prints the firmware telemetry when it stops.\n"
    "Exit status: 0 ran the requested ticks (or until a signal, without --ticks),\n"
    "1 a signal stopped it before the requested ticks, 2 bad usage or configuration\n"
    "(the message names the file and the key, or the interface), 3 the drives did not come up.\n";

struct Options {
  const char* robot = nullptr;       // --robot FILE
  const char* controller = nullptr;  // --controller FILE
  const char* mission = nullptr;     // --mission FILE
  const char* can_log = nullptr;     // --can-log FILE (optional)
  const char* tuning = nullptr;      // --tuning FILE (optional)
  std::uint64_t ticks = 0;           // 0: until a signal
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
      {"--robot", &opt.robot},     {"--controller", &opt.controller}, {"--mission", &opt.mission},
      {"--can-log", &opt.can_log}, {"--tuning", &opt.tuning},         {"--ticks", nullptr},
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
  if (opt.robot == nullptr || opt.controller == nullptr || opt.mission == nullptr) {
    err.why = "missing required option";
    err.arg = opt.robot == nullptr        ? "--robot"
              : opt.controller == nullptr ? "--controller"
                                          : "--mission";
    return false;
  }
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
  std::printf("  events dropped %llu, throttled %llu\n",
              static_cast<unsigned long long>(t.events_dropped),
              static_cast<unsigned long long>(t.events_throttled));
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
void print_slow_group(carril::controller::ControllerTopology& topo) {
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

// The fault that stopped the robot, first in the report: neither a flood of events nor later
// faults can push it out.
void print_first_fault(Controller& ctl, const carril::controller::Hardware& hw,
                       carril::hal::TimeNs t0_ns) {
  if (const Event* e = ctl.first_fault()) {
    char line[160];
    carril::fw::format_event(*e, double(e->t_ns - t0_ns) * 1e-9, line, sizeof line);
    std::printf("first fault: %s\n", line);
  }
  if (hw.can_drives && *hw.can_drives->first_fault() != '\0') {
    std::printf("canopen: first fault: %s\n", hw.can_drives->first_fault());
  }
}

// The CAN side's counters and the master's last fault (after the loop stopped).
void print_can(const carril::controller::Hardware& hw) {
  if (!hw.can_drives) return;
  const carril::hal::canopen::CanopenCounters& c = hw.can_drives->counters();
  const carril::hal::CanBusCounters b = hw.socket->counters();
  std::printf(
      "can %s: tx %llu, rx %llu, tx dropped %llu, rx dropped %llu, error frames %llu, bus-off "
      "%llu, link down %llu\n",
      hw.socket->config().iface.c_str(), static_cast<unsigned long long>(b.tx_frames),
      static_cast<unsigned long long>(b.rx_frames), static_cast<unsigned long long>(b.tx_dropped),
      static_cast<unsigned long long>(b.rx_dropped),
      static_cast<unsigned long long>(b.error_frames), static_cast<unsigned long long>(b.bus_off),
      static_cast<unsigned long long>(hw.socket->link_down_events()));
  std::printf(
      "canopen: syncs %llu, tpdo1 %llu, tpdo2 %llu, heartbeats %llu, emcy %llu, unknown node "
      "%llu, unknown cob %llu, malformed %llu, implausible %llu, feedback bad %llu, heartbeat "
      "losses %llu, faults %llu, fault resets %llu\n",
      static_cast<unsigned long long>(c.syncs), static_cast<unsigned long long>(c.tpdo1),
      static_cast<unsigned long long>(c.tpdo2), static_cast<unsigned long long>(c.heartbeats),
      static_cast<unsigned long long>(c.emcy), static_cast<unsigned long long>(c.unknown_node),
      static_cast<unsigned long long>(c.unknown_cob), static_cast<unsigned long long>(c.malformed),
      static_cast<unsigned long long>(c.implausible),
      static_cast<unsigned long long>(c.feedback_bad),
      static_cast<unsigned long long>(c.heartbeat_losses),
      static_cast<unsigned long long>(c.faults), static_cast<unsigned long long>(c.fault_resets));
  if (*hw.can_drives->last_fault() != '\0') {
    std::printf("canopen: last fault: %s\n", hw.can_drives->last_fault());
  }
  if (hw.tap) {
    std::printf("can log: %llu frames recorded, %llu dropped\n",
                static_cast<unsigned long long>(hw.tap->recorded()),
                static_cast<unsigned long long>(hw.tap->dropped()));
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  UsageError err;
  if (!parse_args(argc, argv, opt, err)) {
    std::fprintf(stderr, "carril_controller: %s: '%s'\n%s", err.why, err.arg, kUsage);
    return 2;
  }
  if (opt.help) {
    std::fputs(kUsage, stdout);
    return 0;
  }

  // Init: everything is read, opened, created and wired here, before the first tick; nothing
  // after this allocates.
  install_signal_handlers();
  // Declared before the firmware that reads its map, so it outlives it.
  carril::controller::LoadedConfig loaded;
  {
    std::string load_error;
    if (!carril::controller::load_controller_config(
            {opt.robot, opt.controller, opt.mission, opt.tuning}, loaded, load_error)) {
      std::fprintf(stderr, "carril_controller: %s\n", load_error.c_str());
      return 2;
    }
  }
  const carril::loader::RobotSpec& robot = loaded.robot;
  const carril::loader::ControllerSpec& spec = loaded.controller;
  const carril::loader::MissionSpec& mission = loaded.mission;
  carril::fw::FirmwareConfig& config = loaded.config;
  const std::unique_ptr<carril::fw::OccupancyGrid>& static_map = loaded.map;
  if (carril::fw::Status s = config.validate(); !s) {
    std::fprintf(stderr, "carril_controller: configuration: %s\n", s.message());
    return 2;
  }
  auto hw = std::make_unique<carril::controller::Hardware>();
  std::string error;
  if (!hw->open(spec, config, opt.can_log, error)) {
    std::fprintf(stderr, "carril_controller: %s\n", error.c_str());
    return 2;
  }
  carril::fw::Status status;
  const auto topo = carril::controller::ControllerTopology::create(config, *hw, status);
  if (!topo) {
    std::fprintf(stderr, "carril_controller: configuration: %s\n", status.message());
    return 2;
  }
  if (hw->tap && !topo->can_log.open(opt.can_log, *hw->tap)) {
    std::fprintf(stderr, "carril_controller: --can-log: %s\n", topo->can_log.error().c_str());
    return 2;
  }
  topo->firmware.controller.set_overrun_limit(static_cast<std::uint32_t>(spec.loop.overrun_limit));
  const carril::fw::FirmwareConfig& cfg = topo->config;
  std::printf("carril_controller: robot %s (%s), controller %s, mission %s %s (%s)\n",
              robot.preset.c_str(), opt.robot, opt.controller, mission.type.c_str(),
              mission.strategy.c_str(), opt.mission);
  if (static_map) {
    const carril::fw::LocalisationConfig& l = cfg.localisation;
    std::printf(
        "carril_controller: map %s: %d x %d cells at %.3f m; localising %s (%.2f, %.2f, %.0f deg), "
        "recovery %s\n",
        mission.map_path.c_str(), static_map->nx(), static_map->ny(), static_map->resolution(),
        l.global ? "globally, not from" : "from", l.initial_pose.x, l.initial_pose.y,
        l.initial_pose.yaw * 180.0 / 3.14159265358979323846, l.mcl.alpha_fast > 0.0 ? "on" : "off");
  }
  std::printf(
      "carril_controller: %s, wheel radius %.3f m, wheelbase %.2f m, track %.2f m, camera %dx%d, "
      "%.0f Hz; lidar %s, imu %s\n",
      cfg.drive.type == carril::fw::DriveType::Mecanum ? "mecanum" : "differential",
      cfg.drive.wheel_radius_m, cfg.drive.wheelbase_m, cfg.drive.track_m, cfg.camera.camera.width,
      cfg.camera.camera.height, cfg.rate_hz, cfg.lidar.present ? "fitted" : "not fitted",
      cfg.watch.imu_present ? "fitted" : "not fitted");
  std::printf("carril_controller: devices: %s\n", hw->describe().c_str());
  std::fflush(stdout);
  // Drive bring-up (boot-up, configuration by SDO, NMT start, enable proven) happens once,
  // before the first tick.
  const carril::hal::DriveInitResult up = topo->devices.drives.init();
  if (!up.ok) {
    std::fprintf(stderr, "carril_controller: drives did not come up: %s\n", up.what);
    topo->can_log.close();
    return 3;
  }
  std::printf("carril_controller: drives up\n");
  if (opt.ticks > 0) {
    std::printf("carril_controller: running %llu ticks\n",
                static_cast<unsigned long long>(opt.ticks));
  } else {
    std::printf("carril_controller: running until SIGINT, SIGTERM or SIGHUP\n");
  }

  // Memory locked (no page fault in the loop), then priorities: the control loop above the slow
  // rate group, so heavy work never delays a tick. Without the privileges both run as ordinary
  // threads, and that is said.
  const char* lock_note = "not asked";
  if (spec.loop.mlockall) {
    lock_note = mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? "locked" : "mlockall refused";
  }
  bool loop_fifo = false;
  if (spec.loop.priority > 0) {
    sched_param loop_param{};
    loop_param.sched_priority = spec.loop.priority;
    loop_fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &loop_param) == 0;
  }
  if (!topo->start_slow_group(loop_fifo)) {
    std::fprintf(stderr, "carril_controller: slow rate group: %s\n", topo->slow_thread.note());
    return 2;
  }
  std::printf("carril_controller: control loop %s %d, slow rate group %s%s%s; memory %s\n",
              loop_fifo ? "SCHED_FIFO" : "SCHED_OTHER", loop_fifo ? spec.loop.priority : 0,
              topo->slow_thread.policy() == carril::hal::PeriodicThread::Policy::Fifo
                  ? "SCHED_FIFO 10"
                  : "SCHED_OTHER",
              *topo->slow_thread.note() ? ": " : "", topo->slow_thread.note(), lock_note);
  std::fflush(stdout);

  // The loop: one firmware step per period. A signal ends it at the next period (the sleep
  // restarts after the handler, so that is at most one period later). A missed deadline is told
  // to the controller (its overrun limit); SIGUSR1 publishes the figures for the slow group.
  carril::controller::ControllerTopology& t = *topo;
  const carril::hal::TimeNs t0_ns = hw->clock.now_ns();
  const auto period_ns = static_cast<carril::hal::TimeNs>(std::llround(1e9 / cfg.rate_hz));
  std::uint64_t missed_seen = 0;
  std::uint64_t periods = 0;
  auto publish_figures = [&] {
    t.firmware.refresh_telemetry();
    const carril::fw::FirmwareTelemetry& tel = t.firmware.telemetry();
    t.loop_figures.write(carril::controller::loop_figures(
        periods, t.loop.missed_deadlines(), t.loop.wake_latency(), tel.controller.tick_p50_us,
        tel.controller.tick_p99_us, tel.controller.tick_max_us));
  };
  const LoopStats loop = t.loop.run(
      [&] {
        if (g_stop.load(std::memory_order_relaxed)) return false;
        if (t.loop.missed_deadlines() != missed_seen) {
          missed_seen = t.loop.missed_deadlines();
          t.firmware.controller.missed_deadline();
        }
        // The firmware's tick touches no heap; Eigen checks that where asserts are on.
        Eigen::internal::set_is_malloc_allowed(false);
        t.app.step();
        Eigen::internal::set_is_malloc_allowed(true);
        ++periods;
        if (g_report.exchange(false, std::memory_order_relaxed)) publish_figures();
        return true;
      },
      opt.ticks);

  // Stopped: the drives first (quick stop on their ramp, then NMT stop), the slow group next
  // (its thread reads what the loop published), then report once.
  t.devices.drives.quick_stop();
  const carril::hal::TimeNs stop_until = hw->clock.now_ns() + 500'000'000;
  carril::hal::WheelFeedbackSet fb;
  for (carril::hal::TimeNs next = hw->clock.now_ns(); next < stop_until;) {
    t.devices.drives.sync();
    t.devices.drives.read(fb);
    bool still = true;
    for (int i = 0; i < fb.count; ++i) {
      still = still && std::fabs(fb.wheel[std::size_t(i)].velocity_radps) < 0.01F;
    }
    if (still) break;
    next += period_ns;
    hw->clock.sleep_until_ns(next);
  }
  if (hw->can_drives) {
    carril::hal::CanBus& bus = hw->tap ? static_cast<carril::hal::CanBus&>(*hw->tap)
                                       : static_cast<carril::hal::CanBus&>(*hw->socket);
    bus.send(carril::hal::canopen::nmt(carril::hal::canopen::NmtCommand::Stop, 0));
  }
  t.slow_thread.stop();
  publish_figures();
  t.firmware.refresh_telemetry();
  const FirmwareTelemetry& all = t.firmware.telemetry();
  const carril::fw::ControllerTelemetry& tel = all.controller;
  const bool interrupted = opt.ticks > 0 && tel.ticks < opt.ticks;
  const int sig = g_stop_signal.load(std::memory_order_relaxed);
  const char* sig_name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
  if (interrupted) {
    std::printf("carril_controller: stopped by a signal (%s) after %llu of %llu ticks\n", sig_name,
                static_cast<unsigned long long>(tel.ticks),
                static_cast<unsigned long long>(opt.ticks));
  } else if (opt.ticks > 0) {
    std::printf("carril_controller: ran the requested %llu ticks\n",
                static_cast<unsigned long long>(opt.ticks));
  } else {
    std::printf("carril_controller: stopped by a signal (%s) after %llu ticks\n", sig_name,
                static_cast<unsigned long long>(tel.ticks));
  }
  print_first_fault(t.firmware.controller, *hw, t0_ns);
  print_telemetry(all, loop);
  {
    // The final figures, printed here with the rest (the slow thread has stopped).
    char line[256];
    t.loop_figures.fetch();
    carril::controller::format_loop_figures(t.loop_figures.value(), line, sizeof line);
    std::printf("%s\n", line);
  }
  print_slow_group(t);
  print_can(*hw);
  print_events(t.firmware.controller, t0_ns);
  if (t.can_log.is_open()) {
    if (!t.can_log.close()) {
      std::fprintf(stderr, "carril_controller: --can-log: could not write %s\n",
                   t.can_log.path().c_str());
    } else {
      std::printf("can log: %s, %zu lines\n", t.can_log.path().c_str(), t.can_log.lines());
    }
  }
  return interrupted ? 1 : 0;
}
