#include "host_sim/app/SimTopology.hpp"

#include "host_sim/scenario/ColorCheck.hpp"

#include <cmath>

namespace carril::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;
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
  c.camera = camera_mount(r.camera);
  // Three missed frames in a row is a dead camera.
  c.camera_timeout_s = std::max(0.2, 3.0 / r.camera.rate_hz);
  c.camera_rate_hz = r.camera.rate_hz;
  c.lidar.present = true;
  c.lidar.x_m = r.lidar.x_m;
  c.lidar.y_m = r.lidar.y_m;
  c.lidar.yaw_rad = r.lidar.yaw_deg * kDeg;
  c.lidar.timeout_s = std::max(0.5, 5.0 / r.lidar.rate_hz);
  c.lidar.rate_hz = r.lidar.rate_hz;
  c.imu_present = true;
  c.health = fw::health_config(c);
  c.detector.line = detector_threshold(s.mission.line_color_name, s.mission.line_color);
  c.detector.end = detector_threshold(s.mission.end_color_name, s.mission.end_color);
  c.strategy.strategy = s.mission.strategy == "line_priority" ? fw::Strategy::LinePriority
                        : s.mission.strategy == "pid"         ? fw::Strategy::Pid
                                                              : fw::Strategy::Marks;
  c.strategy.speed_mps = s.mission.speed_mps;
  c.strategy.pid_straight.speed_mps = s.mission.speed_mps;
  c.strategy.pid_curve.speed_mps = 0.8 * s.mission.speed_mps;
  c.behavior.init_timeout_s = 3.0;
  return c;
}

namespace {
fw::FirmwareConfig tweaked(fw::FirmwareConfig c, const ConfigTweak& tweak) {
  if (tweak) tweak(c);
  return c;
}
}  // namespace

SimTopology::SimTopology(const Scenario& s, std::uint64_t seed, const ConfigTweak& tweak)
    : scenario(s),
      world(s),
      camera_renderer(s, seed),
      lidar(s.robot.lidar, seed),
      drives(world.wheel_count()),
      devices{clock, drives, camera, scanner, imu},
      config(tweaked(firmware_config(s), tweak)),
      controller(std::make_unique<fw::Controller>(config, clock)),
      app(devices, *controller) {}

}  // namespace carril::sim
