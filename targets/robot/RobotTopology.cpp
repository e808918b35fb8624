#include "targets/robot/RobotTopology.hpp"

#include <cmath>
#include <numbers>

namespace carril::robot {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

hal::TimeNs period_ns(double rate_hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / rate_hz));
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
  c.camera.x_m = 0.49;
  c.camera.y_m = 0.0;
  c.camera.z_m = 0.90;
  c.camera.tilt_rad = 55.0 * kDeg;
  c.camera.hfov_rad = 54.2 * kDeg;
  c.camera.width = 640;
  c.camera.height = 480;
  // Same rules as the simulator: three missed 30 Hz frames, five missed 20 Hz scans.
  c.camera_timeout_s = 0.2;
  c.lidar.present = true;  // campero has one; its backend comes with the CAN/Ethernet drivers
  c.lidar.x_m = 0.45;
  c.lidar.y_m = -0.35;
  c.lidar.yaw_rad = -45.0 * kDeg;
  c.lidar.timeout_s = 0.5;
  c.lidar.rate_hz = 20.0;
  c.camera_rate_hz = 30.0;
  c.imu_present = false;  // no IMU backend yet (hal::NullImu)
  c.health = fw::health_config(c);
  c.strategy.strategy = fw::Strategy::LinePriority;  // mecanum: the thesis's best on campero
  c.strategy.speed_mps = 0.5;
  return c;
}

RobotTopology::RobotTopology()
    : drives(4),  // mecanum: front-left, front-right, rear-left, rear-right
      devices{clock, drives, camera, scanner, imu},
      config(robot_config()),
      controller(config, clock),
      app(devices, controller),
      loop(clock, period_ns(config.rate_hz)) {}

}  // namespace carril::robot
