#include "targets/robot/RobotTopology.hpp"

#include <cmath>

namespace carril::robot {

namespace {
hal::TimeNs period_ns(double rate_hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / rate_hz));
}

constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}
}  // namespace

fw::Status declare_tasks(fw::LineFirmware& f) {
  using fw::TaskSpec;
  const fw::TaskRates r = fw::task_rates(f.config());
  // Read top to bottom: the order tasks run in within a tick is the order data flows.
  // bind<component method>(name, rate [Hz], offset [ticks], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::SensorWatch::run>("health", r.control_hz, 0, us(20), &f.watch),
      TaskSpec::bind<&fw::WheelOdometry::run>("odometry", r.control_hz, 0, us(20), &f.odometry),
      TaskSpec::bind<&fw::LinePerception::run>("perception", r.camera_hz, 0, us(400),
                                               &f.perception),
      TaskSpec::bind<&fw::ObstacleSensing::run>("obstacles", r.lidar_hz, r.scan_offset, us(60),
                                                &f.obstacle_sensing),
      TaskSpec::bind<&fw::MissionRunner::run>("mission", r.control_hz, 0, us(80), &f.runner),
      TaskSpec::bind<&fw::MotionOutput::run>("motion", r.control_hz, 0, us(20), &f.output),
      TaskSpec::bind<&fw::LineFirmware::refresh_telemetry>("telemetry", r.telemetry_hz,
                                                           r.telemetry_offset, us(50), &f),
  };
  return f.controller.declare(table);
}

fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              fw::EventSink& events) {
  using fw::TaskSpec;
  if (fw::Status s = slow.init(kSlowRateHz, &events); !s) return s;
  // bind<component method>(name, rate [Hz], offset [cycles], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::StatusReporter::run>("status", 1.0, 0, us(2000), &reporter),
  };
  return slow.add_all(table);
}

bool RobotTopology::start_slow_group(bool loop_is_fifo) {
  return slow_thread.start(
      "carril-slow", period_ns(kSlowRateHz), loop_is_fifo ? kSlowPriority : 0,
      [](void* ctx) {
        auto* t = static_cast<RobotTopology*>(ctx);
        t->slow.cycle(t->clock.now_ns(), t->clock);
      },
      this);
}

std::unique_ptr<RobotTopology> RobotTopology::create(const fw::FirmwareConfig& config,
                                                     fw::Status& error) {
  error = config.validate();
  if (!error) return nullptr;
  auto topo = std::make_unique<RobotTopology>(config);
  error = declare_tasks(topo->firmware);
  if (!error) return nullptr;
  error = declare_slow_tasks(topo->slow, topo->reporter, topo->slow_events);
  if (!error) return nullptr;
  return topo;
}

RobotTopology::RobotTopology(const fw::FirmwareConfig& cfg)
    : drives(fw::DriveKinematics(cfg.drive).wheel_count()),  // in the kinematics' wheel order
      devices{clock, drives, camera, scanner, imu},
      config(cfg),
      firmware(config, clock),
      app(devices, firmware.controller),
      loop(clock, period_ns(config.rate_hz)),
      reporter(firmware.status, console) {}

}  // namespace carril::robot
