#include "firmware/app/Firmware.hpp"

#include <algorithm>
#include <cstring>

namespace carril::fw {

Firmware::Firmware(const FirmwareConfig& cfg, const hal::Clock& clock)
    : kinematics(cfg.drive),
      bus(cfg.footprint(), cfg.lidar.x_m, cfg.lidar.y_m, cfg.lidar.yaw_rad,
          cfg.runner.lost_turn_reach_m(cfg.footprint())),
      controller(clock, cfg.rate_hz, bus.frame, bus.command, runner),
      watch(cfg.watch, cfg.lidar.present, bus.frame, bus.odometry, controller),
      odometry(kinematics, bus.frame, bus.odometry, cfg.gyro_heading && cfg.watch.imu_present),
      localisation(cfg.localisation, cfg.lidar.mount(), cfg.map, bus.frame, bus.odometry, bus.pose),
      perception(cfg.camera, bus.frame, bus.odometry, bus.line, controller),
      obstacle_sensing(cfg.lidar, bus.frame, bus.odometry, bus.obstacles, controller),
      mapping(cfg.mapping, cfg.rate_hz, cfg.lidar.mount(), bus.frame, bus.pose, cfg.map,
              &bus.costmap),
      mission(cfg.follow_line, cfg.footprint(), kinematics.holonomic(), cfg.lidar.present,
              bus.odometry, bus.line, bus.obstacles),
      goto_mission(cfg.goto_mission, cfg.footprint(), kinematics.holonomic(), bus.pose,
                   bus.costmap),
      waypoints(cfg.waypoints, cfg.footprint(), kinematics.holonomic(), bus.pose, bus.costmap),
      coverage(cfg.mission == MissionKind::Coverage
                   ? make_coverage_mission(cfg.coverage, cfg.footprint(), kinematics.holonomic(),
                                           bus.pose, bus.costmap,
                                           cfg.map != nullptr ? *cfg.map : no_map_)
                   : nullptr),
      runner(cfg.runner, 1.0 / cfg.rate_hz, kinematics.wheel_count(), select_mission(cfg.mission),
             bus.frame, bus.odometry, bus.obstacles, bus.motion, controller, cfg.watch.imu_present),
      output(cfg.limits, kinematics, 1.0 / cfg.rate_hz, bus.frame, bus.motion, bus.command,
             controller),
      cfg_(cfg) {
  // Without a costmap nothing is published on it: both then check with the lidar alone.
  mission.watch_costmap(bus.costmap);
  runner.watch_costmap(bus.costmap);
  if (cfg.localisation.enabled) runner.watch_pose(bus.pose);
}

namespace {
std::int64_t ns_of_us(double us) {
  return static_cast<std::int64_t>(us * 1e3);
}
}  // namespace

Status Firmware::declare_tasks() {
  const TaskRates r = task_rates(cfg_);
  const TaskBudgets& b = cfg_.tasks;
  // Read top to bottom: the order tasks run in within a tick is the order data flows.
  // bind<component method>(name, rate [Hz], offset [ticks], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&SensorWatch::run>("health", r.control_hz, 0, ns_of_us(b.health_us), &watch),
      TaskSpec::bind<&WheelOdometry::run>("odometry", r.control_hz, 0, ns_of_us(b.odometry_us),
                                          &odometry),
      TaskSpec::bind<&Localisation::run>("localisation", r.control_hz, 0,
                                         ns_of_us(b.localisation_us), &localisation),
      TaskSpec::bind<&LinePerception::run>("perception", r.camera_hz, 0, ns_of_us(b.perception_us),
                                           &perception),
      TaskSpec::bind<&ObstacleSensing::run>("obstacles", r.lidar_hz, r.scan_offset,
                                            ns_of_us(b.obstacles_us), &obstacle_sensing),
      // The costmap from the lidar (and the map), every tick: goto and coverage plan on it,
      // follow_line's bypass checks its lanes on it. Returns at once when none is built.
      TaskSpec::bind<&Mapping::run>("mapping", r.control_hz, 0, ns_of_us(b.mapping_us), &mapping),
      TaskSpec::bind<&MissionRunner::run>("mission", r.control_hz, 0, ns_of_us(b.mission_us),
                                          &runner),
      TaskSpec::bind<&MotionOutput::run>("motion", r.control_hz, 0, ns_of_us(b.motion_us), &output),
      TaskSpec::bind<&Firmware::refresh_telemetry>("telemetry", r.telemetry_hz, r.telemetry_offset,
                                                   ns_of_us(b.telemetry_us), this),
  };
  return controller.declare(table);
}

Status Firmware::init_status() const {
  if (const Status& s = mapping.init_status(); !s) return s;
  return localisation.init_status();
}

TaskRates task_rates(const FirmwareConfig& c) {
  TaskRates r;
  r.control_hz = c.rate_hz;
  r.camera_hz = std::min(c.camera.rate_hz, c.rate_hz);
  r.lidar_hz = std::min(c.lidar.rate_hz, c.rate_hz);
  r.scan_offset = 1 % TaskTable::divisor_for(c.rate_hz, r.lidar_hz);
  r.telemetry_offset = TaskTable::divisor_for(c.rate_hz, r.telemetry_hz) - 1;
  return r;
}

void Firmware::refresh_telemetry() {
  FirmwareTelemetry& t = telemetry_;
  controller.fill_telemetry(t.controller);
  t.mission = active_mission().name();
  active_mission().counters(t.mission_counters);
  t.mapping = mapping.telemetry();
  t.localisation = localisation.telemetry();
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

Mission& Firmware::select_mission(MissionKind kind) {
  switch (kind) {
    case MissionKind::Goto:
      return goto_mission;
    case MissionKind::Waypoints:
      return waypoints;
    case MissionKind::Coverage:
      return *coverage;
    case MissionKind::FollowLine:
      break;
  }
  return mission;
}

const Mission& Firmware::active_mission() const {
  return const_cast<Firmware*>(this)->select_mission(cfg_.mission);
}

std::uint32_t Firmware::mission_counter(const char* name) const {
  MissionCounters c;
  active_mission().counters(c);
  for (const MissionCounter& m : c) {
    if (std::strcmp(m.name, name) == 0) return m.value;
  }
  return 0;
}

}  // namespace carril::fw
