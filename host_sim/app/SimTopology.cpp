#include "host_sim/app/SimTopology.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "host_sim/scenario/ColorCheck.hpp"

namespace carril::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;

constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}
}  // namespace

fw::FirmwareConfig firmware_config(const Scenario& s) {
  const RobotSpec& r = s.robot;
  fw::FirmwareConfig c;
  c.rate_hz = r.control_rate_hz;
  c.drive = drive_geometry(r);
  c.footprint_length_m = r.length_m;
  c.footprint_width_m = r.width_m;
  c.limits.max_speed_mps = r.limits.max_speed_mps;
  c.limits.max_yaw_rate_radps = r.limits.max_yaw_rate_radps;
  c.limits.max_accel_mps2 = r.limits.max_accel_mps2;
  c.limits.max_wheel_speed_radps = r.limits.max_wheel_speed_radps;
  c.camera.camera = camera_mount(r.camera);
  c.camera.rate_hz = r.camera.rate_hz;
  c.lidar.present = true;
  c.lidar.x_m = r.lidar.x_m;
  c.lidar.y_m = r.lidar.y_m;
  c.lidar.yaw_rad = r.lidar.yaw_deg * kDeg;
  c.lidar.rate_hz = r.lidar.rate_hz;
  c.watch.imu_present = true;
  c.camera.detector.line = detector_threshold(s.mission.line_color_name, s.mission.line_color);
  c.camera.detector.end = detector_threshold(s.mission.end_color_name, s.mission.end_color);
  fw::StrategyConfig& st = c.follow_line.strategy;
  st.strategy = s.mission.strategy == "line_priority" ? fw::Strategy::LinePriority
                : s.mission.strategy == "pid"         ? fw::Strategy::Pid
                                                      : fw::Strategy::Marks;
  st.speed_mps = s.mission.speed_mps;
  st.pid_straight.speed_mps = s.mission.speed_mps;
  st.pid_curve.speed_mps = 0.8 * s.mission.speed_mps;
  c.follow_line.behavior.init_timeout_s = 3.0;
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

namespace {
fw::FirmwareConfig checked(fw::FirmwareConfig c, const ConfigTweak& tweak, const Scenario& s) {
  if (tweak) tweak(c);
  if (const fw::Status st = c.validate(); !st) {
    throw std::invalid_argument(s.source_path + ": firmware configuration: " + st.message());
  }
  return c;
}

std::unique_ptr<fw::LineFirmware> wired(const fw::FirmwareConfig& c, const hal::Clock& clock,
                                        const Scenario& s) {
  auto f = std::make_unique<fw::LineFirmware>(c, clock);
  if (const fw::Status st = declare_tasks(*f); !st) {
    throw std::invalid_argument(s.source_path + ": task table: " + st.message());
  }
  return f;
}
}  // namespace

SimTopology::SimTopology(const Scenario& s, std::uint64_t seed, const ConfigTweak& tweak)
    : scenario(s),
      world(s),
      camera_renderer(s, seed),
      lidar(s.robot.lidar, seed),
      drives(world.wheel_count()),
      devices{clock, drives, camera, scanner, imu},
      config(checked(firmware_config(s), tweak, s)),
      firmware(wired(config, clock, s)),
      app(devices, firmware->controller),
      reporter(firmware->status, console),
      slow_divisor(fw::TaskTable::divisor_for(config.rate_hz, kSlowRateHz)) {
  if (const fw::Status st = declare_slow_tasks(slow, reporter, slow_events); !st) {
    throw std::invalid_argument(s.source_path + ": slow rate group: " + st.message());
  }
}

}  // namespace carril::sim
