#include "targets/robot/RobotTopology.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace carril::robot {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

hal::TimeNs period_ns(double rate_hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / rate_hz));
}

constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}
}  // namespace

fw::FirmwareConfig robot_config() {
  fw::FirmwareConfig c;
  c.rate_hz = 100.0;
  c.drive.type = fw::DriveType::Mecanum;
  c.drive.wheel_radius_m = 0.127;
  c.drive.wheelbase_m = 0.60;
  c.drive.track_m = 0.60;
  c.footprint_length_m = 0.98;
  c.footprint_width_m = 0.78;
  c.limits.max_speed_mps = 1.5;
  c.limits.max_yaw_rate_radps = 1.5;
  c.limits.max_accel_mps2 = 1.0;
  c.limits.max_wheel_speed_radps = 12.0;
  // Camera on the front mast, looking down at the floor ahead of the bumper.
  c.camera.camera.x_m = 0.49;
  c.camera.camera.y_m = 0.0;
  c.camera.camera.z_m = 0.90;
  c.camera.camera.tilt_rad = 55.0 * kDeg;
  c.camera.camera.hfov_rad = 54.2 * kDeg;
  c.camera.camera.width = 640;
  c.camera.camera.height = 480;
  c.camera.rate_hz = 30.0;
  c.lidar.present = true;  // campero has one; its backend comes with the CAN/Ethernet drivers
  c.lidar.x_m = 0.45;
  c.lidar.y_m = -0.35;
  c.lidar.yaw_rad = -45.0 * kDeg;
  c.lidar.rate_hz = 20.0;
  c.watch.imu_present = false;  // no IMU backend yet (hal::NullImu)
  c.follow_line.strategy.strategy = fw::Strategy::LinePriority;  // mecanum: the thesis's best
  c.follow_line.strategy.speed_mps = 0.5;
  fw::apply_sensor_rates(c);
  return c;
}

fw::Status declare_tasks(fw::LineFirmware& f) {
  using fw::TaskSpec;
  const fw::FirmwareConfig& c = f.config();
  // Sensor tasks run at their sensor's rate, or every tick when the sensor is faster (then the
  // newest frame or scan is taken and the ones between are skipped).
  const double camera_hz = std::min(c.camera.rate_hz, c.rate_hz);
  const double lidar_hz = std::min(c.lidar.rate_hz, c.rate_hz);
  // Scans are processed one tick after frames, which spreads the two heaviest tasks.
  const std::uint32_t scan_offset = 1 % fw::TaskTable::divisor_for(c.rate_hz, lidar_hz);
  // Telemetry (percentiles over every histogram) on the last tick of its period.
  const std::uint32_t telemetry_offset = fw::TaskTable::divisor_for(c.rate_hz, 10.0) - 1;
  // Read top to bottom: the order tasks run in within a tick is the order data flows.
  // bind<component method>(name, rate [Hz], offset [ticks], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::SensorWatch::run>("health", c.rate_hz, 0, us(20), &f.watch),
      TaskSpec::bind<&fw::WheelOdometry::run>("odometry", c.rate_hz, 0, us(20), &f.odometry),
      TaskSpec::bind<&fw::LinePerception::run>("perception", camera_hz, 0, us(400), &f.perception),
      TaskSpec::bind<&fw::ObstacleSensing::run>("obstacles", lidar_hz, scan_offset, us(60),
                                                &f.obstacle_sensing),
      TaskSpec::bind<&fw::MissionRunner::run>("mission", c.rate_hz, 0, us(80), &f.runner),
      TaskSpec::bind<&fw::MotionOutput::run>("motion", c.rate_hz, 0, us(20), &f.output),
      TaskSpec::bind<&fw::LineFirmware::refresh_telemetry>("telemetry", 10.0, telemetry_offset,
                                                           us(50), &f),
  };
  for (const TaskSpec& t : table) {
    if (fw::Status s = f.controller.add_task(t); !s) return s;
  }
  return f.controller.check();
}

fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              fw::EventSink& events) {
  using fw::TaskSpec;
  if (fw::Status s = slow.init(kSlowRateHz, &events); !s) return s;
  // bind<component method>(name, rate [Hz], offset [cycles], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::StatusReporter::run>("status", 1.0, 0, us(2000), &reporter),
  };
  for (const TaskSpec& t : table) {
    if (fw::Status s = slow.add(t); !s) return s;
  }
  return fw::Status::ok();
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
    : drives(4),  // mecanum: front-left, front-right, rear-left, rear-right
      devices{clock, drives, camera, scanner, imu},
      config(cfg),
      firmware(config, clock),
      app(devices, firmware.controller),
      loop(clock, period_ns(config.rate_hz)),
      reporter(firmware.status, console) {}

}  // namespace carril::robot
