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
  const fw::FirmwareConfig& c = f.config();
  // Read top to bottom: the order tasks run in within a tick is the order data flows.
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::SensorWatch::run>("health", c.rate_hz, 0, us(20), &f.watch),
      TaskSpec::bind<&fw::WheelOdometry::run>("odometry", c.rate_hz, 0, us(20), &f.odometry),
      TaskSpec::bind<&fw::LinePerception::run>("perception", c.camera.rate_hz, 0, us(400),
                                               &f.perception),
      TaskSpec::bind<&fw::ObstacleSensing::run>("obstacles", c.lidar.rate_hz, 1, us(60),
                                                &f.obstacle_sensing),
      TaskSpec::bind<&fw::MissionRunner::run>("mission", c.rate_hz, 0, us(80), &f.runner),
      TaskSpec::bind<&fw::MotionOutput::run>("motion", c.rate_hz, 0, us(20), &f.output),
      TaskSpec::bind<&fw::LineFirmware::refresh_telemetry>("telemetry", 10.0, 9, us(50), &f),
  };
  for (const TaskSpec& t : table) {
    if (fw::Status s = f.controller.add_task(t); !s) return s;
  }
  return f.controller.check();
}

std::unique_ptr<RobotTopology> RobotTopology::create(const fw::FirmwareConfig& config,
                                                     fw::Status& error) {
  error = config.validate();
  if (!error) return nullptr;
  auto topo = std::make_unique<RobotTopology>(config);
  error = declare_tasks(topo->firmware);
  if (!error) return nullptr;
  return topo;
}

RobotTopology::RobotTopology(const fw::FirmwareConfig& cfg)
    : drives(fw::DriveKinematics(cfg.drive).wheel_count()),  // in the kinematics' wheel order
      devices{clock, drives, camera, scanner, imu},
      config(cfg),
      firmware(config, clock),
      app(devices, firmware.controller),
      loop(clock, period_ns(config.rate_hz)) {}

}  // namespace carril::robot
