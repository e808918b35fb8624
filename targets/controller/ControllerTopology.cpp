#include "targets/controller/ControllerTopology.hpp"

#include <cmath>
#include <ctime>

#include "firmware/kinematics/DriveKinematics.hpp"

namespace carril::controller {

namespace {
hal::TimeNs period_ns(double rate_hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / rate_hz));
}

constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}

constexpr hal::TimeNs kMs = 1'000'000;
constexpr int kCanLogRecords = 16384;  // 11 s of a 4-drive bus at 100 Hz between two drains

// The candump log's time: wall-clock seconds, as candump writes them, from the loop's monotonic
// clock plus an offset taken at init (the tap records inside the tick: no extra clock call).
struct LogTime {
  hal::LinuxClock* clock = nullptr;
  hal::TimeNs offset_ns = 0;
};
LogTime g_log_time;

hal::TimeNs log_now(void*) {
  return g_log_time.clock->now_ns() + g_log_time.offset_ns;
}
}  // namespace

fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              LoopReportPrinter& loop_report, CanLogFile& can_log,
                              fw::EventSink& events) {
  using fw::TaskSpec;
  if (fw::Status s = slow.init(kSlowRateHz, &events); !s) return s;
  // bind<component method>(name, rate [Hz], offset [cycles], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::StatusReporter::run>("status", 1.0, 0, us(2000), &reporter),
      TaskSpec::bind<&LoopReportPrinter::run>("loop_report", kSlowRateHz, 0, us(2000),
                                              &loop_report),
      TaskSpec::bind<&CanLogFile::run>("can_log", kSlowRateHz, 0, us(20000), &can_log),
  };
  return slow.add_all(table);
}

hal::canopen::CanopenConfig canopen_config(const loader::ControllerSpec& spec, double rate_hz,
                                           double max_wheel_radps) {
  const loader::CanSpec& can = spec.can;
  hal::canopen::CanopenConfig c;
  c.wheels = static_cast<int>(can.drives.size());
  for (int i = 0; i < c.wheels && i < hal::kMaxWheels; ++i) {
    const loader::ControllerDriveSpec& d = can.drives[std::size_t(i)];
    hal::canopen::DriveSetup& s = c.drive[i];
    s.node = static_cast<std::uint8_t>(d.node);
    s.units.counts_per_rev = d.counts_per_rev;
    s.units.gear_ratio = d.gear_ratio;
    s.inverted = d.inverted;
    s.max_wheel_radps = max_wheel_radps;
    s.accel_radps2 = can.accel_radps2;
    s.decel_radps2 = can.decel_radps2;
    s.quick_stop_decel_radps2 = can.quick_stop_decel_radps2;
    s.heartbeat_ms = static_cast<std::uint16_t>(can.drive_heartbeat_ms);
    s.master_node = static_cast<std::uint8_t>(can.master_node);
    s.master_timeout_ms = static_cast<std::uint16_t>(can.master_timeout_ms);
    c.name[i] = d.name.c_str();
  }
  c.master_node = static_cast<std::uint8_t>(can.master_node);
  c.master_heartbeat_ns = can.master_heartbeat_ms * kMs;
  c.control_period_ns = period_ns(rate_hz);
  c.heartbeat_consumer_ns = can.drive_timeout_ms * kMs;
  c.sdo_timeout_ns = static_cast<hal::TimeNs>(std::llround(can.sdo_timeout_s * 1e9));
  c.boot_timeout_ns = static_cast<hal::TimeNs>(std::llround(can.boot_timeout_s * 1e9));
  c.enable_timeout_ns = static_cast<hal::TimeNs>(std::llround(can.enable_timeout_s * 1e9));
  c.bring_up_poll_ns = period_ns(rate_hz);
  c.max_reads = can.max_reads_per_tick;
  c.feedback_missed_syncs = can.feedback_missed_syncs;
  return c;
}

bool Hardware::open(const loader::ControllerSpec& spec, const fw::FirmwareConfig& fw,
                    const char* can_log_path, std::string& error) {
  // CAN bus and drives.
  if (spec.can.interface == "none") {
    if (can_log_path != nullptr) {
      error = "--can-log: can.interface is none (" + spec.source_path + "): no bus to log";
      return false;
    }
    null_drives =
        std::make_unique<hal::NullWheelDrives>(fw::DriveKinematics(fw.drive).wheel_count());
  } else {
    hal::SocketCanBus::Config cc;
    cc.iface = spec.can.interface;
    cc.send_deadline_ns = period_ns(fw.rate_hz);  // a setpoint a period old is worse than none
    cc.tx_batch = 32;  // a period's RPDOs, SYNC and heartbeat in one system call (flush())
    cc.rx_batch = 32;  // a period's TPDOs, heartbeats and answers in one system call
    hal::SocketCanBus::OpenResult r = hal::SocketCanBus::open(cc);
    if (!r.bus) {
      error = spec.source_path + ": can.interface: " + r.error;
      return false;
    }
    socket = std::move(r.bus);
    hal::CanBus* bus = socket.get();
    if (can_log_path != nullptr) {
      timespec real{};
      clock_gettime(CLOCK_REALTIME, &real);
      g_log_time.clock = &clock;
      g_log_time.offset_ns =
          (hal::TimeNs(real.tv_sec) * 1'000'000'000 + real.tv_nsec) - clock.now_ns();
      tap = std::make_unique<hal::CanLogTap>(*socket, kCanLogRecords, spec.can.interface.c_str(),
                                             &log_now, nullptr);
      bus = tap.get();
    }
    waiter = std::make_unique<hal::canopen::ClockSleepWaiter>(clock);
    can_drives = std::make_unique<hal::canopen::CanopenWheelDrives>(
        *bus, clock, *waiter, canopen_config(spec, fw.rate_hz, fw.limits.max_wheel_speed_radps));
    if (*can_drives->config_error() != '\0') {
      error = spec.source_path + ": can: " + can_drives->config_error();
      return false;
    }
  }
  // Sensors.
  if (spec.lidar.source == loader::SensorSource::Scip) {
    lidar = std::make_unique<hal::ScipLidar>();
    hal::ScipLidarConfig lc;
    lc.host = spec.lidar.host.c_str();
    lc.port = static_cast<std::uint16_t>(spec.lidar.port);
    if (!lidar->start(lc)) {
      error = spec.source_path + ": sensors.lidar: " + lidar->error();
      return false;
    }
  }
  if (spec.camera.source == loader::SensorSource::Shm) {
    camera_link = std::make_unique<hal::ShmSensorReader>();
    if (!camera_link->open(spec.camera.name.c_str())) {
      error = spec.source_path + ": sensors.camera: " + camera_link->error();
      return false;
    }
  }
  if (spec.imu.source == loader::SensorSource::Shm &&
      (!camera_link || spec.imu.name != spec.camera.name)) {
    imu_link = std::make_unique<hal::ShmSensorReader>();
    if (!imu_link->open(spec.imu.name.c_str())) {
      error = spec.source_path + ": sensors.imu: " + imu_link->error();
      return false;
    }
  }
  imu_from_camera_link_ = spec.imu.source == loader::SensorSource::Shm && !imu_link;
  return true;
}

hal::WheelDrives& Hardware::drives() {
  if (can_drives) return *can_drives;
  return *null_drives;
}
hal::Camera& Hardware::camera() {
  if (camera_link) return camera_link->camera();
  return null_camera;
}
hal::RangeScanner& Hardware::scanner() {
  if (lidar) return *lidar;
  return null_scanner;
}
hal::Imu& Hardware::imu() {
  if (imu_link) return imu_link->imu();
  if (imu_from_camera_link_) return camera_link->imu();
  return null_imu;
}

std::string Hardware::describe() const {
  std::string s;
  if (can_drives) {
    s = std::to_string(can_drives->count()) + " CiA 402 drives on " + socket->config().iface;
    if (tap) s += " (logged)";
  } else {
    s = "no CAN bus (can.interface none): " + std::to_string(null_drives->count()) + " null drives";
  }
  s += lidar ? "; lidar SCIP 2.0" : "; no lidar";
  s += camera_link ? "; camera shared memory" : "; no camera";
  s += (imu_link || imu_from_camera_link_) ? "; imu shared memory" : "; no imu";
  return s;
}

bool ControllerTopology::start_slow_group(bool loop_is_fifo) {
  return slow_thread.start(
      "carril-slow", period_ns(kSlowRateHz), loop_is_fifo ? kSlowPriority : 0,
      [](void* ctx) {
        auto* t = static_cast<ControllerTopology*>(ctx);
        t->slow.cycle(t->hw.clock.now_ns(), t->hw.clock);
      },
      this);
}

std::unique_ptr<ControllerTopology> ControllerTopology::create(const fw::FirmwareConfig& config,
                                                               Hardware& hw, fw::Status& error) {
  error = config.validate();
  if (!error) return nullptr;
  auto topo = std::make_unique<ControllerTopology>(config, hw);
  error = topo->firmware.init_status();
  if (!error) return nullptr;
  error = topo->firmware.declare_tasks();
  if (!error) return nullptr;
  error = declare_slow_tasks(topo->slow, topo->reporter, topo->loop_report, topo->can_log,
                             topo->slow_events);
  if (!error) return nullptr;
  return topo;
}

ControllerTopology::ControllerTopology(const fw::FirmwareConfig& cfg, Hardware& h)
    : hw(h),
      devices{hw.clock, hw.drives(), hw.camera(), hw.scanner(), hw.imu()},
      config(cfg),
      firmware(config, hw.clock),
      app(devices, firmware.controller),
      loop(hw.clock, period_ns(config.rate_hz)),
      reporter(firmware.status, console),
      loop_report(loop_figures, console) {}

}  // namespace carril::controller
