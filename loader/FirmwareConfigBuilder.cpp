#include "loader/FirmwareConfigBuilder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

#include "loader/ColorThreshold.hpp"

namespace carril::loader {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Where a firmware field that comes from the robot or the mission was written: the name
// FirmwareConfig::validate() gives it, and its key in the robot file or the mission.
struct Source {
  const char* field;
  const char* key;
  bool mission;  // in the mission rather than the robot file
};

const Source kSources[] = {
    {"robot.control_rate_hz", "control_rate_hz", false},
    {"robot.footprint_length_m", "body.length_m", false},
    {"robot.footprint_width_m", "body.width_m", false},
    {"drive.wheel_radius_m", "wheels.radius_m", false},
    {"drive.wheelbase_m", "wheels.wheelbase_m", false},
    {"drive.track_m", "wheels.track_m", false},
    {"limits.max_speed_mps", "limits.max_speed_mps", false},
    {"limits.max_yaw_rate_radps", "limits.max_yaw_rate_radps", false},
    {"limits.max_accel_mps2", "limits.max_accel_mps2", false},
    {"limits.max_wheel_speed_radps", "limits.max_wheel_speed_radps", false},
    {"camera.x_m", "camera.x_m", false},
    {"camera.y_m", "camera.y_m", false},
    {"camera.z_m", "camera.z_m", false},
    {"camera.tilt_rad", "camera.tilt_deg", false},
    {"camera.hfov_rad", "camera.hfov_deg", false},
    {"camera.width", "camera.width", false},
    {"camera.height", "camera.height", false},
    {"camera.rate_hz", "camera.rate_hz", false},
    {"robot.camera.rate_hz", "camera.rate_hz", false},
    {"lidar.x_m", "lidar.x_m", false},
    {"lidar.y_m", "lidar.y_m", false},
    {"lidar.yaw_rad", "lidar.yaw_deg", false},
    {"lidar.rate_hz", "lidar.rate_hz", false},
    {"robot.lidar.rate_hz", "lidar.rate_hz", false},
    {"lidar.reliable_range_m", "lidar.reliable_range_m", false},
    {"robot.limits.max_speed_mps", "limits.max_speed_mps", false},
    {"detector.line", "line_color", true},
    {"detector.end", "end_color", true},
    {"strategy.speed_mps", "speed_mps", true},
    {"strategy.pid_straight", "speed_mps", true},
    {"strategy.pid_curve", "speed_mps", true},
};

std::string file_or(const std::string& path, const char* what) {
  return path.empty() ? std::string(what) : path;
}

// A rejection of the robot-and-mission stage, traced to the robot file or the mission.
std::string explain_base(const RobotSpec& robot, const MissionSpec& mission,
                         const std::string& message) {
  const std::string field = message.substr(0, message.find(": "));
  for (const Source& s : kSources) {
    if (field != s.field) continue;
    const std::string file = s.mission ? file_or(mission.source_path, "the mission")
                                       : file_or(robot.source_path, "the robot description");
    return file + ": " + s.key + ": rejected by the firmware (" + message + ")";
  }
  return file_or(robot.source_path, "the robot description") + " with " +
         file_or(mission.source_path, "the mission") + ": rejected by the firmware (" + message +
         ")";
}

BuildResult rejected(std::string error, const fw::Status& st) {
  BuildResult r;
  r.error = std::move(error);
  r.firmware_error = st.message();
  return r;
}

// The costmap: built whenever a lidar is fitted (follow_line checks its bypass on it, goto plans
// on it); the inscribed radius is the footprint's half width. Terrain (the 3D lidar's elevation
// map) is built for goto only: follow_line keeps to its tape.
void apply_mapping(const RobotSpec& r, bool goto_mission, fw::FirmwareConfig& c) {
  fw::MappingConfig& m = c.mapping;
  m.enabled = r.lidar.present || (goto_mission && r.lidar3d.present);
  m.costmap.inflation.inscribed_radius_m = 0.5 * r.width_m;
  m.costmap.inflation.inflation_radius_m = std::max(0.55, 0.5 * r.width_m + 0.3);
  m.terrain = goto_mission && r.lidar3d.present;
  if (!m.terrain) return;
  m.lidar3d.x_m = r.lidar3d.x_m;
  m.lidar3d.y_m = r.lidar3d.y_m;
  m.lidar3d.z_m = r.lidar3d.z_m;
  m.lidar3d.yaw_rad = r.lidar3d.yaw_deg * kDeg;
  m.elevation.size_x_m = m.costmap.size_x_m;
  m.elevation.size_y_m = m.costmap.size_y_m;
  m.elevation.resolution_m = m.costmap.resolution_m;
  m.elevation.min_range_m =
      std::max(r.lidar3d.range_min_m, 0.5 * std::hypot(r.length_m, r.width_m));
  m.elevation.max_range_m = r.lidar3d.range_max_m;
  m.profile.max_slope_deg = r.traversability.max_slope_deg;
  m.profile.max_step_up_m = r.traversability.max_step_up_m;
  m.profile.max_step_down_m = r.traversability.max_step_down_m;
  // The blind zone round the start: where the lowest ring cannot reach the ground.
  const double z = r.lidar3d.z_m;
  const double lowest = std::max(1e-3, -r.lidar3d.vertical_min_deg * kDeg);
  const double rmin = r.lidar3d.range_min_m;
  const double blind =
      std::max(z / std::tan(lowest), rmin > z ? std::sqrt(rmin * rmin - z * z) : 0.0);
  m.start_free_radius_m = std::max(0.5 * std::hypot(r.length_m, r.width_m), blind) + 0.2;
}

// goto: the goal (odometry frame), the speed and the follower.
void apply_goto(const MissionSpec& mission, fw::FirmwareConfig& c) {
  c.mission = fw::MissionKind::Goto;
  fw::GotoConfig& g = c.goto_mission;
  g.goal = {mission.goal_x_m, mission.goal_y_m, mission.goal_yaw_deg * kDeg};
  for (const GoalSpec& k : mission.goals) g.goals.push_back({k.x_m, k.y_m, k.yaw_deg * kDeg});
  g.speed_mps = mission.speed_mps;
  g.follower = mission.follower == "vff" ? fw::GotoFollower::Vff : fw::GotoFollower::PurePursuit;
  g.planner.allow_unknown = mission.allow_unknown;
  g.pure_pursuit.cruise_speed_mps = mission.speed_mps;
  g.vff.cruise_speed_mps = mission.speed_mps;
  g.pure_pursuit.max_yaw_rate_radps =
      std::min(g.pure_pursuit.max_yaw_rate_radps, c.limits.max_yaw_rate_radps);
  g.vff.max_yaw_rate_radps = std::min(g.vff.max_yaw_rate_radps, c.limits.max_yaw_rate_radps);
}

// waypoints: the targets (odometry frame), laps, reach radius; VFF at the mission's speed.
void apply_waypoints(const MissionSpec& mission, fw::FirmwareConfig& c) {
  c.mission = fw::MissionKind::Waypoints;
  fw::WaypointConfig& w = c.waypoints;
  for (const GoalSpec& t : mission.targets) w.targets.push_back(fw::Vec2(t.x_m, t.y_m));
  w.laps = std::uint32_t(mission.laps);
  w.reach_radius_m = mission.reach_radius_m;
  w.speed_mps = mission.speed_mps;
  w.vff.cruise_speed_mps = mission.speed_mps;
  w.vff.max_yaw_rate_radps = std::min(w.vff.max_yaw_rate_radps, c.limits.max_yaw_rate_radps);
}

// coverage: mode, tool (the robot's width unless given), area, speed, time limit.
void apply_coverage(const RobotSpec& r, const MissionSpec& mission, fw::FirmwareConfig& c) {
  c.mission = fw::MissionKind::Coverage;
  fw::CoverageConfig& k = c.coverage;
  k.mode =
      mission.coverage_mode == "vacuum" ? fw::CoverageMode::Vacuum : fw::CoverageMode::Systematic;
  k.tool_width_m = mission.tool_width_m > 0.0 ? mission.tool_width_m : r.width_m;
  k.speed_mps = mission.speed_mps;
  // The followers drive the mission's speed (the score's lower bound is taken at it), turning
  // no faster than the robot can.
  k.sweep.cruise_speed_mps = mission.speed_mps;
  k.sweep.max_yaw_rate_radps = c.limits.max_yaw_rate_radps;
  k.sweep.period_s = 1.0 / c.rate_hz;
  k.transit_speed_mps =
      mission.transit_speed_mps > 0.0 ? mission.transit_speed_mps : mission.speed_mps;
  k.transit_pursuit.cruise_speed_mps = k.transit_speed_mps;
  k.transit_pursuit.max_yaw_rate_radps = c.limits.max_yaw_rate_radps;
  k.lane_overlap = mission.lane_overlap;
  k.wall_clearance_m = mission.wall_clearance_m;
  k.max_time_s = mission.max_time_s;
  for (const GoalSpec& p : mission.area) k.area.push_back(fw::Vec2(p.x_m, p.y_m));
  k.vacuum.forward_speed_mps = std::min(k.vacuum.forward_speed_mps, mission.speed_mps);
  k.vacuum.spiral_speed_mps = std::min(k.vacuum.spiral_speed_mps, mission.speed_mps);
}

}  // namespace

fw::DriveGeometry drive_geometry(const RobotSpec& robot) {
  fw::DriveGeometry g;
  g.type = robot.drive == DriveType::Mecanum ? fw::DriveType::Mecanum : fw::DriveType::Differential;
  g.wheel_radius_m = robot.wheel_radius_m;
  g.wheelbase_m = robot.wheelbase_m;
  g.track_m = robot.track_m;
  return g;
}

fw::CameraMount camera_mount(const CameraSpec& s) {
  fw::CameraMount m;
  m.x_m = s.x_m;
  m.y_m = s.y_m;
  m.z_m = s.z_m;
  m.tilt_rad = s.tilt_deg * kDeg;
  m.hfov_rad = s.hfov_deg * kDeg;
  m.width = s.width;
  m.height = s.height;
  return m;
}

BuildResult build_firmware_config(const RobotSpec& r, const MissionSpec& mission,
                                  const Tuning* tuning) {
  fw::FirmwareConfig c;
  c.rate_hz = r.control_rate_hz;
  c.drive = drive_geometry(r);
  c.footprint_length_m = r.length_m;
  c.footprint_width_m = r.width_m;
  c.runner.check.round_body = r.round_body;
  c.limits.max_speed_mps = r.limits.max_speed_mps;
  c.limits.max_yaw_rate_radps = r.limits.max_yaw_rate_radps;
  c.limits.max_accel_mps2 = r.limits.max_accel_mps2;
  c.limits.max_wheel_speed_radps = r.limits.max_wheel_speed_radps;
  c.camera.camera = camera_mount(r.camera);
  c.camera.rate_hz = r.camera.rate_hz;
  c.lidar.present = r.lidar.present;
  c.lidar.x_m = r.lidar.x_m;
  c.lidar.y_m = r.lidar.y_m;
  c.lidar.yaw_rad = r.lidar.yaw_deg * kDeg;
  c.lidar.rate_hz = r.lidar.rate_hz;
  c.lidar.reliable_range_m =
      r.lidar.reliable_range_m > 0.0 ? r.lidar.reliable_range_m : r.lidar.range_max_m;
  c.watch.imu_present = r.imu.present;
  c.gyro_heading = r.imu.present && r.imu.gyro_heading;
  c.camera.detector.line = detector_threshold(mission.line_color_name, mission.line_color);
  c.camera.detector.end = detector_threshold(mission.end_color_name, mission.end_color);
  fw::StrategyConfig& st = c.follow_line.strategy;
  if (mission.strategy == "line_priority") {
    st.strategy = fw::Strategy::LinePriority;
  } else if (mission.strategy == "pid") {
    st.strategy = fw::Strategy::Pid;
  } else if (mission.strategy == "marks") {
    st.strategy = fw::Strategy::Marks;
  } else {
    BuildResult bad;
    bad.error = file_or(mission.source_path, "the mission") +
                ": strategy: expected line_priority, marks or pid, got \"" + mission.strategy +
                "\"";
    return bad;
  }
  st.speed_mps = mission.speed_mps;
  // pid has a speed for straights and one for curves: the mission's speed and 80% of it.
  st.pid_straight.speed_mps = mission.speed_mps;
  st.pid_curve.speed_mps = 0.8 * mission.speed_mps;
  apply_mapping(r, mission.type == "goto", c);
  if (mission.type == "goto") apply_goto(mission, c);
  if (mission.type == "waypoints") apply_waypoints(mission, c);
  if (mission.type == "coverage") apply_coverage(r, mission, c);
  fw::apply_sensor_rates(c);
  if (const fw::Status s = c.validate(); !s) {
    return rejected(explain_base(r, mission, s.message()), s);
  }

  // Settings on top, mission first; a rejection names the setting that set the field.
  struct Stage {
    const std::vector<Setting>* settings;
    std::string file;
  };
  const Stage stages[] = {
      {&mission.settings, file_or(mission.source_path, "the mission")},
      {tuning != nullptr ? &tuning->settings : nullptr,
       tuning != nullptr ? file_or(tuning->source_path, "the tuning") : ""},
  };
  for (const Stage& stage : stages) {
    if (stage.settings == nullptr || stage.settings->empty()) continue;
    std::string error;
    if (!apply_settings(*stage.settings, c, error)) return rejected(error, fw::Status::ok());
    if (const fw::Status s = c.validate(); !s) {
      std::string why;
      if (!explain_with_settings(*stage.settings, s.message(), why)) {
        why = stage.file + ": rejected by the firmware (" + s.message() + ")";
      }
      return rejected(why, s);
    }
  }
  // The sweep's turns brake for the robot's yaw acceleration, whatever set it.
  if (mission.type == "coverage") {
    c.coverage.sweep.max_yaw_accel_radps2 = c.limits.max_yaw_accel_radps2;
  }
  BuildResult ok;
  ok.ok = true;
  ok.config = c;
  return ok;
}

}  // namespace carril::loader
