#pragma once
// A scenario file, parsed and validated: everything the simulator builds a run from.
// Units: metres, radians (angles in files are degrees; the loader converts), seconds.
// World frame: x forward at yaw 0, y left, yaw counter-clockwise.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace carril::sim {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

struct Vec2 {
  double x = 0.0, y = 0.0;
};

struct Pose2 {
  double x = 0.0, y = 0.0, yaw_rad = 0.0;
};

enum class DriveType { Differential, Mecanum };

// Downward-tilted pinhole camera, mounted looking forward along the robot's x axis.
struct CameraSpec {
  double x_m = 0.0, y_m = 0.0, z_m = 0.5;  // optical centre in the robot frame [m]
  double tilt_deg = 45.0;                  // optical axis below horizontal [deg]
  double hfov_deg = 60.0;                  // horizontal field of view [deg]
  int width = 640, height = 480;           // [px]
  double rate_hz = 30.0;                   // frame rate [Hz]
  double noise_std = 0.0;                  // Gaussian pixel noise, per channel [0..255 units]
};

struct LidarSpec {
  double x_m = 0.0, y_m = 0.0;  // mount position in the robot frame [m]
  double yaw_deg = 0.0;         // mount heading relative to robot x [deg]
  double fov_deg = 270.0;       // field of view, centred on the mount heading [deg]
  int beams = 541;
  double range_min_m = 0.05, range_max_m = 20.0;  // [m]
  double rate_hz = 20.0;                          // [Hz]
  double noise_std_m = 0.0;                       // Gaussian range noise [m]
};

struct LimitsSpec {
  double max_speed_mps = 1.0;            // body linear speed [m/s]
  double max_yaw_rate_radps = 1.5;       // body yaw rate [rad/s]
  double max_accel_mps2 = 1.0;           // body linear acceleration [m/s^2]
  double max_wheel_speed_radps = 10.0;   // each wheel [rad/s]
  double max_wheel_accel_radps2 = 20.0;  // each wheel [rad/s^2]
};

// A robot preset (config/robots/<name>.yaml) after the scenario's overrides are applied.
struct RobotSpec {
  std::string preset;  // campero | pioneer3at
  DriveType drive = DriveType::Differential;
  double length_m = 0.5, width_m = 0.5;  // body footprint [m]
  double mass_kg = 30.0;
  double wheel_radius_m = 0.1;     // [m]
  double wheelbase_m = 0.4;        // front-rear axle distance (mecanum) [m]
  double track_m = 0.4;            // left-right wheel distance [m]
  double cruise_speed_mps = 0.5;   // default mission speed [m/s]
  double control_rate_hz = 100.0;  // firmware tick rate [Hz]
  CameraSpec camera;
  LidarSpec lidar;
  LimitsSpec limits;
  Pose2 start;  // from the scenario
};

struct MissionSpec {
  std::string type = "follow_line";  // follow_line
  std::string strategy = "pid";      // line_priority | marks | pid
  Rgb line_color{255, 255, 255};
  std::string line_color_name = "white";  // name as written, or "[r, g, b]"
  Rgb end_color{255, 255, 0};
  std::string end_color_name = "yellow";
  double speed_mps = 0.5;  // cruise speed; the preset's when the file omits it [m/s]
};

struct LineSpec {
  Rgb color;
  double width_m = 0.05;
  // The tape's centre line in path order; arcs are discretised by the loader into points no more
  // than 2 cm apart, in the arc's own direction.
  std::vector<Vec2> points;
  bool from_arc = false;
};

struct MarkSpec {
  Rgb color;
  Vec2 center;
  double radius_m = 0.15;
};

enum class ObstacleShape { Box, Cylinder };

struct ObstacleSpec {
  ObstacleShape shape = ObstacleShape::Box;
  Vec2 center;
  double yaw_rad = 0.0;
  double size_x_m = 1.0, size_y_m = 1.0;  // box, full lengths [m]
  double radius_m = 0.5;                  // cylinder [m]
};

struct WallSpec {
  std::vector<Vec2> points;  // polyline, at least 2 points
  double thickness_m = 0.1;
};

enum class TerrainType { Ramp, Step };

struct TerrainSpec {
  TerrainType type = TerrainType::Ramp;
  Vec2 center;
  double yaw_rad = 0.0;
  double length_m = 1.0, width_m = 1.0;
  double angle_deg = 0.0;  // ramp
  double height_m = 0.0;   // step
};

struct ExpectSpec {
  std::optional<bool> end_reached;
  std::optional<int> max_collisions;
  std::optional<double> max_cross_track_rms_m;
  std::optional<double> min_progress;
  std::optional<int> min_laps;
  std::optional<double> max_end_stop_error_m;  // [m]
  bool any() const {
    return end_reached || max_collisions || max_cross_track_rms_m || min_progress || min_laps ||
           max_end_stop_error_m;
  }
};

struct Scenario {
  std::string source_path;  // file it was read from
  std::string name;
  std::string description;
  double duration_s = 60.0;
  std::uint64_t seed = 0;
  Rgb floor{128, 128, 128};
  RobotSpec robot;
  MissionSpec mission;
  std::vector<LineSpec> lines;
  std::vector<MarkSpec> marks;
  std::vector<ObstacleSpec> obstacles;
  std::vector<WallSpec> walls;
  std::vector<TerrainSpec> terrain;
  ExpectSpec expect;
};

}  // namespace carril::sim
