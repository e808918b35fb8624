#pragma once
// A robot's description as config/robots/<name>.yaml writes it: drive and geometry, sensor mounts
// and rates, limits, which sensors are fitted. Units as in the file: metres, seconds, and degrees
// for mount angles (the firmware configuration builder converts them to radians).
// Robot frame: x forward, y left, z up, origin at the body centre on the floor.
// The defaults below only fill what a file leaves out where the format allows it (a lidar that is
// not fitted); every value of a real robot comes from its file.
#include <optional>
#include <string>

namespace carril::loader {

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
  double exposure = 1.0;                   // simulated: every rendered level times this [-]
};

struct LidarSpec {
  bool present = true;          // a lidar is fitted (else the firmware does without one)
  double x_m = 0.0, y_m = 0.0;  // mount position in the robot frame [m]
  double yaw_deg = 0.0;         // mount heading relative to robot x [deg]
  double fov_deg = 270.0;       // field of view, centred on the mount heading [deg]
  int beams = 541;
  double range_min_m = 0.05, range_max_m = 20.0;  // [m]
  // How far it sees what the protective fields must see (a dark, matt person's legs): its
  // datasheet's range at low remission; 0 in the file: range_max_m [m].
  double reliable_range_m = 0.0;
  double rate_hz = 20.0;     // [Hz]
  double noise_std_m = 0.0;  // Gaussian range noise [m]
  double dropout = 0.0;      // simulated: fraction of beams with no return, drawn per beam [-]
};

// A 3D lidar (e.g. a Velodyne HDL-32E): `rings` beams evenly spread over
// [vertical_min_deg, vertical_max_deg], `azimuths` firings per 360 deg sweep. Simulated only for
// now (host_sim/sensors/Lidar3dSim). Defaults: the HDL-32E, kept cheap to simulate (20 m).
struct Lidar3dSpec {
  bool present = false;              // a 3D lidar is fitted (a robot file may leave it out)
  double x_m = 0.0, y_m = 0.0;       // mount position in the robot frame [m]
  double z_m = 0.5;                  // optical centre above the floor under the robot [m]
  double yaw_deg = 0.0;              // mount heading relative to robot x [deg]
  int rings = 32;                    // beams stacked vertically
  double vertical_min_deg = -30.67;  // lowest ring's elevation (below horizontal < 0) [deg]
  double vertical_max_deg = 10.67;   // highest ring's elevation [deg]
  int azimuths = 1800;               // firings per sweep (1800: 0.2 deg) [1]
  double rate_hz = 10.0;             // sweeps per second [Hz]
  double range_min_m = 1.0;          // blind zone round the sensor: nearer returns dropped [m]
  double range_max_m = 20.0;         // farther returns dropped [m]
  double noise_std_m = 0.0;          // Gaussian range noise along the beam [m]
  double drop_probability = 0.0;     // each beam's chance of returning nothing [0..1]
};

struct ImuSpec {
  bool present = true;       // an IMU is fitted: the firmware checks its samples
  bool gyro_heading = true;  // the odometry takes its heading from the gyro (needs present)
  // Simulated only: what the yaw rate carries besides the truth.
  double gyro_noise_std_radps = 0.0;  // white noise on each sample [rad/s]
  double gyro_bias_radps = 0.0;       // constant bias left after calibration [rad/s]
};

struct LimitsSpec {
  double max_speed_mps = 1.0;            // body linear speed [m/s]
  double max_yaw_rate_radps = 1.5;       // body yaw rate [rad/s]
  double max_accel_mps2 = 1.0;           // body linear acceleration [m/s^2]
  double max_wheel_speed_radps = 10.0;   // each wheel [rad/s]
  double max_wheel_accel_radps2 = 20.0;  // each wheel [rad/s^2]
};

// What ground the robot can drive over (the `traversability:` section), for the terrain costmap;
// converted to the firmware's TraversabilityProfile when the configuration is built.
struct TraversabilitySpec {
  double max_slope_deg = 8.0;     // steepest ground slope it climbs or descends [deg]
  double max_step_up_m = 0.03;    // highest step it climbs between neighbouring cells [m]
  double max_step_down_m = 0.10;  // deepest drop it drives down [m]
};

// What the real machine can physically drive over (not the planner's limits, which keep a
// margin): the simulator blocks the robot beyond the first two and counts a fall beyond the third.
struct TerrainLimitsSpec {
  double max_slope_deg = 15.0;    // steepest ground it can drive onto, along its heading [deg]
  double max_step_up_m = 0.05;    // highest step it can climb [m]
  double max_step_down_m = 0.10;  // deepest drop it can drive off without falling [m]
};

// A robot description (config/robots/<name>.yaml); in the simulator, after the scenario's
// overrides are applied.
// `localisation:` (optional): how Monte Carlo localisation models this robot's lidar and odometry
// on a map (fw::MclConfig's fields of the same names). A key left out keeps the firmware's
// default. Both targets read it from the robot file: the simulator runs the model the robot runs.
struct LocalisationModelSpec {
  std::optional<double> sigma_hit_m;                     // hit spread of the tracking model [m]
  std::optional<double> beam_correlation;                // [-]
  std::optional<double> alpha1, alpha2, alpha3, alpha4;  // odometry noise (AMCL's alphas)
  std::optional<bool> surface_distance;           // distances to the walls' faces, not centres
  std::optional<double> search_sigma_hit_m;       // the search model's hit spread [m]
  std::optional<double> search_beam_correlation;  // [-]
};

struct RobotSpec {
  std::string preset;       // the file's `name`: campero | pioneer3at | ...
  std::string source_path;  // the file it was read from ("" when not read from a file)
  DriveType drive = DriveType::Differential;
  double length_m = 0.5, width_m = 0.5;  // body footprint [m]
  // body.shape: round: the simulator's body is the disc inscribed in the footprint (the firmware
  // keeps the footprint's square round it).
  bool round_body = false;
  double mass_kg = 30.0;
  double wheel_radius_m = 0.1;     // [m]
  double wheelbase_m = 0.4;        // front-rear axle distance (mecanum) [m]
  double track_m = 0.4;            // left-right wheel distance [m]
  double cruise_speed_mps = 0.5;   // default mission speed [m/s]
  double control_rate_hz = 100.0;  // firmware tick rate [Hz]
  CameraSpec camera;
  LidarSpec lidar;
  Lidar3dSpec lidar3d;  // `lidar3d:` (optional; absent: not fitted)
  ImuSpec imu;
  LimitsSpec limits;
  TraversabilitySpec traversability;
  TerrainLimitsSpec terrain_limits;
  LocalisationModelSpec localisation;
  Pose2 start;  // set by a scenario; the robot target leaves it at the origin
};

}  // namespace carril::loader
