#include "firmware/app/LineFirmware.hpp"

#include <algorithm>
#include <cstring>

namespace carril::fw {

LineFirmware::LineFirmware(const FirmwareConfig& cfg, const hal::Clock& clock)
    : kinematics(cfg.drive),
      bus(cfg.footprint(), cfg.lidar.x_m, cfg.lidar.y_m, cfg.lidar.yaw_rad),
      controller(clock, cfg.rate_hz, bus.frame, bus.command, runner),
      watch(cfg.watch, cfg.lidar.present, bus.frame, bus.odometry, controller),
      odometry(kinematics, bus.frame, bus.odometry),
      perception(cfg.camera, bus.frame, bus.odometry, bus.line, controller),
      obstacle_sensing(cfg.lidar, bus.frame, bus.odometry, bus.obstacles, controller),
      mission(cfg.follow_line, cfg.footprint(), kinematics.holonomic(), cfg.lidar.present,
              bus.odometry, bus.line, bus.obstacles),
      runner(cfg.runner, 1.0 / cfg.rate_hz, kinematics.wheel_count(), mission, bus.frame,
             bus.odometry, bus.obstacles, bus.motion, controller, cfg.watch.imu_present),
      output(cfg.limits, kinematics, 1.0 / cfg.rate_hz, bus.frame, bus.motion, bus.command,
             controller),
      cfg_(cfg) {}

TaskRates task_rates(const FirmwareConfig& c) {
  TaskRates r;
  r.control_hz = c.rate_hz;
  r.camera_hz = std::min(c.camera.rate_hz, c.rate_hz);
  r.lidar_hz = std::min(c.lidar.rate_hz, c.rate_hz);
  r.scan_offset = 1 % TaskTable::divisor_for(c.rate_hz, r.lidar_hz);
  r.telemetry_offset = TaskTable::divisor_for(c.rate_hz, r.telemetry_hz) - 1;
  return r;
}

void LineFirmware::refresh_telemetry() {
  FirmwareTelemetry& t = telemetry_;
  controller.fill_telemetry(t.controller);
  t.mission = mission.name();
  mission.counters(t.mission_counters);
  t.runner = runner.telemetry();
  t.watch = watch.telemetry();
  t.odometry = odometry.telemetry();
  t.output = output.telemetry();
  t.perception = perception.telemetry();
  t.obstacles = obstacle_sensing.telemetry();
  t.odom = bus.odometry.get().pose;

  StatusSnapshot& s = status.write_slot();
  s.t_ns = bus.frame.get().now_ns;
  s.ticks = t.controller.ticks;
  s.tick_overruns = t.controller.tick_overruns;
  s.tick_max_us = t.controller.tick_max_us;
  s.state = t.controller.state;
  s.phase = t.controller.phase;
  s.status = t.controller.status;
  s.fault = t.controller.fault;
  s.odom = t.odom;
  s.frames = t.watch.camera_frames;
  s.scans = t.watch.scans;
  s.events_dropped = t.controller.events_dropped;
  status.publish();
}

std::uint32_t LineFirmware::mission_counter(const char* name) const {
  MissionCounters c;
  mission.counters(c);
  for (const MissionCounter& m : c) {
    if (std::strcmp(m.name, name) == 0) return m.value;
  }
  return 0;
}

}  // namespace carril::fw
