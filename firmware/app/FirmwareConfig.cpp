#include "firmware/app/FirmwareConfig.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

std::span<const Param<TaskBudgets>> TaskBudgets::params() {
  using C = TaskBudgets;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, health_us, "us", 1.0, 1e6,
                   "the sensor health rules (SensorWatch): a run over it is an overrun, counted in "
                   "the task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, odometry_us, "us", 1.0, 1e6,
                   "wheel odometry: a run over it is an overrun, counted in the task's telemetry "
                   "and reported as a throttled event"),
      CARRIL_PARAM(
          C, localisation_us, "us", 1.0, 1e6,
          "localisation on the map (a bounded piece of the filter per tick): a run over it is an "
          "overrun, counted in the task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, perception_us, "us", 1.0, 1e6,
                   "the tape detector on a camera frame: a run over it is an overrun, counted in "
                   "the task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, obstacles_us, "us", 1.0, 1e6,
                   "the lidar scan into the obstacle field: a run over it is an overrun, counted "
                   "in the task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, mapping_us, "us", 1.0, 1e6,
                   "one piece of the costmap's work: a run over it is an overrun, counted in the "
                   "task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, mission_us, "us", 1.0, 1e6,
                   "the mission runner and its mission (goto's and coverage's plans are spread "
                   "over ticks within it): a run over it is an overrun, counted in the task's "
                   "telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, motion_us, "us", 1.0, 1e6,
                   "the motion limits and the wheel setpoints: a run over it is an overrun, "
                   "counted in the task's telemetry and reported as a throttled event"),
      CARRIL_PARAM(C, telemetry_us, "us", 1.0, 1e6,
                   "the telemetry and status snapshot (10 Hz): a run over it is an overrun, "
                   "counted in the task's telemetry and reported as a throttled event"),
  };
  return kParams;
}

Status TaskBudgets::validate() const {
  return Checks("tasks").params(*this, params()).result();
}

std::span<const Param<FirmwareConfig>> FirmwareConfig::params() {
  // The robot file's control_rate_hz and body.length_m / width_m: read with these ranges.
  static constexpr Param<FirmwareConfig> kParams[] = {
      param(&FirmwareConfig::rate_hz,
            {"control_rate_hz", "Hz", 10.0, 1000.0, "the control loop's rate: the robot file's",
             nullptr, false}),
      CARRIL_PARAM(FirmwareConfig, footprint_length_m, "m", 0.1, 5.0,
                   "the body's length: the robot file's body.length_m", nullptr, false),
      CARRIL_PARAM(FirmwareConfig, footprint_width_m, "m", 0.1, 5.0,
                   "the body's width: the robot file's body.width_m", nullptr, false),
  };
  return kParams;
}

Status FirmwareConfig::validate() const {
  Checks c("robot");
  c.params(*this, params())
      .nested(drive.validate())
      .nested(limits.validate())
      .nested(camera.validate())
      .nested(watch.validate())
      .nested(runner.validate())
      .nested(follow_line.validate())
      .nested(mapping.validate())
      .nested(tasks.validate());
  if (mission == MissionKind::Goto) {
    c.nested(goto_mission.validate())
        .fail_if(!mapping.enabled, "mapping.enabled",
                 "must be true for goto (it plans on the costmap)");
  }
  if (mission == MissionKind::Waypoints) {
    c.nested(waypoints.validate())
        .fail_if(!mapping.enabled, "mapping.enabled",
                 "must be true for waypoints (VFF is pushed by the costmap's obstacles)");
  }
  if (mission == MissionKind::Coverage) {
    c.nested(coverage.validate())
        .fail_if(!mapping.enabled, "mapping.enabled", "must be true for coverage");
  }
  if (lidar.present) c.nested(lidar.validate());
  c.nested(check_stopping_reach(*this));
  c.nested(localisation.validate());
  const bool have_map = map != nullptr && !map->empty();
  c.fail_if(localisation.enabled && !have_map, "localisation.enabled",
            "needs a static map (none given)")
      .fail_if(have_map && !localisation.enabled, "localisation.enabled",
               "must be true with a static map (the costmap is in the map frame)");
  if (have_map && mapping.enabled) {
    c.fail_if(!lidar.present, "lidar", "a 2D lidar is needed to localise on a map")
        .nested(costmap_for_map(mapping.costmap, map->info()).validate());
  }
  return c.result();
}

Status check_stopping_reach(const FirmwareConfig& c) {
  const SafetyFieldsConfig& f = c.runner.fields;
  if (!f.enabled || !c.lidar.present) return Status::ok();
  const double v = c.limits.max_speed_mps;
  const Footprint fp = c.footprint();
  const double stop = f.stop_m(v);
  if (f.max_field_m > 0.0 && stop > f.max_field_m) {
    return Status::error(
        "robot.limits.max_speed_mps: %g m/s needs a protective field of %.2f m (reaction %.3g s, "
        "%g m/s^2, margin %g m), longer than runner.fields.max_field_m %g m",
        v, stop, f.reaction_s(), f.decel_mps2, f.margin_m, f.max_field_m);
  }
  // The warning field's far corners, seen from the lidar.
  const double ahead = fp.half_length_m + f.warning_m(v) - c.lidar.x_m;
  const double side = fp.half_width_m + f.warning_side_m(v) + std::fabs(c.lidar.y_m);
  const double reach = std::hypot(ahead, side);
  if (reach > c.lidar.reliable_range_m) {
    return Status::error(
        "robot.limits.max_speed_mps: %g m/s needs its warning field to reach %.2f m from the lidar "
        "(stop %.2f m: reaction %.3g s, %g m/s^2; a person at %g m/s), beyond "
        "lidar.reliable_range_m %g m",
        v, reach, stop, f.reaction_s(), f.decel_mps2, f.approach_speed_mps,
        c.lidar.reliable_range_m);
  }
  return Status::ok();
}

void apply_sensor_rates(FirmwareConfig& c) {
  c.watch.camera_timeout_s = std::max(0.2, 3.0 / c.camera.rate_hz);
  c.watch.scanner_timeout_s = std::max(0.5, 5.0 / c.lidar.rate_hz);
  const int scans = static_cast<int>(std::lround(c.lidar.rate_hz * 0.25));
  c.lidar.health.window_scans = std::clamp(scans, 2, ScanHealth::kMaxWindow);
  const int frames = static_cast<int>(std::lround(c.camera.rate_hz * 0.2));
  c.camera.health.blank_frames = std::max(frames, 2);
  c.watch.imu.max_yaw_rate_radps = 4.0 * c.limits.max_yaw_rate_radps;
  // The protective fields react within a scan and a tick (plus the drive's latency), and stop at
  // the limiter's deceleration.
  c.runner.fields.scan_period_s = c.lidar.present ? 1.0 / c.lidar.rate_hz : 0.0;
  c.runner.fields.tick_s = 1.0 / c.rate_hz;
  c.runner.fields.decel_mps2 = c.limits.max_accel_mps2;
  c.runner.check.yaw_decel_radps2 = c.limits.max_yaw_accel_radps2;
}

}  // namespace carril::fw
