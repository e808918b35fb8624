#include "host_sim/app/HilMain.hpp"

#include <time.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "hal/linux/SocketCanBus.hpp"
#include "host_sim/app/HilRun.hpp"
#include "host_sim/output/RunOutputs.hpp"
#include "loader/ControllerLoader.hpp"
#include "loader/SafeCreate.hpp"

namespace carril::sim {

namespace {
void sleep_until(const timespec& t) {
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) != 0) {
  }
}
void advance(timespec& t, long ns) {
  t.tv_nsec += ns;
  while (t.tv_nsec >= 1'000'000'000L) {
    t.tv_nsec -= 1'000'000'000L;
    ++t.tv_sec;
  }
}
}  // namespace

int run_hil(const Scenario& scenario, std::uint64_t seed, const std::string& out_dir,
            const HilOptions& opt, const std::atomic<int>& signal) {
  HilConfig cfg;
  std::string error;
  if (opt.controller_path.empty()) {
    std::fprintf(stderr, "carril_sim: --hil needs --controller FILE (config/controller/*.yaml)\n");
    return 2;
  }
  if (!loader::load_controller(opt.controller_path, scenario.robot, cfg.controller, error)) {
    std::fprintf(stderr, "carril_sim: --controller: %s\n", error.c_str());
    return 2;
  }
  if (opt.scip_port < 0 || opt.scip_port > 65535) {
    std::fprintf(stderr, "carril_sim: --scip-port: expected 0 to 65535, got %d\n", opt.scip_port);
    return 2;
  }
  cfg.scip_port = static_cast<std::uint16_t>(opt.scip_port);
  cfg.shm_name = opt.shm;
  for (const std::string& text : opt.inject) {
    HilInjection inj;
    if (!parse_injection(text, scenario.robot.drive == DriveType::Mecanum ? 4 : 2, inj, error)) {
      std::fprintf(stderr, "carril_sim: --inject: %s\n", error.c_str());
      return 2;
    }
    cfg.injections.push_back(inj);
  }
  hal::SocketCanBus::Config cc;
  cc.iface = opt.can_iface;
  cc.tx_backlog = 256;
  cc.send_deadline_ns = 50'000'000;
  cc.tx_batch = 64;  // the drives' frames of a step in one system call
  cc.rx_batch = 64;  // the controller's frames of a step in one system call
  hal::SocketCanBus::OpenResult bus = hal::SocketCanBus::open(cc);
  if (!bus.bus) {
    std::fprintf(stderr, "carril_sim: --can: %s\n", bus.error.c_str());
    return 2;
  }
  std::FILE* log = nullptr;
  const std::string log_part = opt.can_log + ".part";
  if (!opt.can_log.empty()) {
    std::string why;
    log = loader::open_new_output(log_part, why);
    if (log == nullptr) {
      std::fprintf(stderr, "carril_sim: --can-log: %s\n", why.c_str());
      return 2;
    }
    cfg.can_log = log;
    cfg.can_log_iface = opt.can_iface;
  }
  auto run = std::make_unique<HilRun>(scenario, seed, *bus.bus, cfg);
  if (!run->open(error)) {
    std::fprintf(stderr, "carril_sim: %s\n", error.c_str());
    if (log != nullptr) std::fclose(log);
    return 2;
  }
  const double duration = opt.duration_s > 0.0 ? opt.duration_s : scenario.duration_s;
  std::printf(
      "carril_sim: HIL: scenario %s, robot %s, %d emulated drives on %s (controller file %s), "
      "lidar SCIP 2.0 on 127.0.0.1:%d, camera and IMU in shared memory %s, %.0f s in real time\n",
      scenario.name.c_str(), scenario.robot.preset.c_str(), run->wheels(), opt.can_iface.c_str(),
      opt.controller_path.c_str(), opt.scip_port, opt.shm.empty() ? "(none)" : opt.shm.c_str(),
      duration);
  std::fflush(stdout);

  // Real time on absolute deadlines, one world step per period. The world's clock is the wall
  // clock: a step that comes late covers the time that went by (up to HilRun::kMaxStepS; more
  // is dropped and counted), so the drives' heartbeats and PDOs keep their rates as the
  // controller sees them even when this machine cannot keep the step rate.
  timespec next{}, last{};
  clock_gettime(CLOCK_MONOTONIC, &next);
  last = next;
  const long step_ns = static_cast<long>(HilRun::kStepS * 1e9);
  double next_status_s = 1.0;
  std::uint64_t late = 0;
  double dropped_s = 0.0;
  while (signal.load() == 0 && run->sim_time_s() < duration) {
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    const double elapsed =
        double(now.tv_sec - last.tv_sec) + double(now.tv_nsec - last.tv_nsec) * 1e-9;
    last = now;
    if (elapsed > HilRun::kMaxStepS) dropped_s += elapsed - HilRun::kMaxStepS;
    run->step(elapsed);
    if (run->sim_time_s() >= next_status_s) {
      std::printf("%s\n", run->status_line().c_str());
      std::fflush(stdout);
      if (log != nullptr) std::fflush(log);
      next_status_s += 1.0;
    }
    advance(next, step_ns);
    clock_gettime(CLOCK_MONOTONIC, &now);
    const long behind_ns =
        (now.tv_sec - next.tv_sec) * 1'000'000'000L + (now.tv_nsec - next.tv_nsec);
    if (behind_ns <= 0) {
      sleep_until(next);
    } else {
      ++late;
      next = now;  // the next step a full period from now
    }
  }
  std::printf("%s\n", run->status_line().c_str());
  std::printf(
      "carril_sim: HIL ended after %.2f s (%s): laps %d, progress %.3f, collisions %d; frames "
      "from the controller %llu, to it %llu (refused %llu); SYNC %.1f Hz, TPDO %.1f /s; late "
      "steps %llu, time dropped %.2f s\n",
      run->sim_time_s(), signal.load() != 0 ? "signal" : "duration", run->metrics().laps(),
      run->metrics().progress(), run->metrics().collisions(),
      static_cast<unsigned long long>(run->frames_from_wire()),
      static_cast<unsigned long long>(run->frames_to_wire()),
      static_cast<unsigned long long>(run->wire_refused()), run->sync_rate_hz(),
      run->tpdo_rate_hz(), static_cast<unsigned long long>(late), dropped_s);
  int rc = 0;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);  // checked by prepare_output_dir already
  if (!write_file_atomic(out_dir + "/hil_summary.json", run->summary_json(), error)) {
    std::fprintf(stderr, "carril_sim: writing outputs: %s\n", error.c_str());
    rc = 2;
  } else {
    std::printf("carril_sim: wrote %s/hil_summary.json\n", out_dir.c_str());
  }
  if (log != nullptr) {
    const bool ok =
        std::fclose(log) == 0 && std::rename(log_part.c_str(), opt.can_log.c_str()) == 0;
    if (!ok) {
      std::fprintf(stderr, "carril_sim: --can-log: could not write %s\n", opt.can_log.c_str());
      rc = 2;
    }
  }
  return rc;
}

}  // namespace carril::sim
