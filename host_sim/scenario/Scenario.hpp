#pragma once
// A scenario file, parsed and validated: everything the simulator builds a run from.
// Units: metres, radians (angles in files are degrees; the loader converts), seconds.
// World frame: x forward at yaw 0, y left, yaw counter-clockwise.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::loader {
// loader/OccupancyMapFile.hpp; declared only, so that this header needs no firmware (Eigen)
// headers.
struct OccupancyMapData;
}  // namespace carril::loader

namespace carril::sim {

// The robot and the mission are described by the shared loader's types (loader/), the same
// on the robot target.
using loader::CameraSpec;
using loader::DriveType;
using loader::ImuSpec;
using loader::LidarSpec;
using loader::LimitsSpec;
using loader::MissionSpec;
using loader::Pose2;
using loader::Rgb;
using loader::RobotSpec;

struct Vec2 {
  double x = 0.0, y = 0.0;
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
  double height_m = 1.0;  // top above the ground under its centre [m] (the 3D lidar sees it)
};

// Something that moves on its own (a person crossing the tape, a forklift in an aisle, another
// robot): a disc or a box that walks a polyline at a constant speed from start_s on, then stands
// at its end. Seen by the lidar and the physics as any obstacle; it pushes what it meets.
struct MoverSpec {
  ObstacleShape shape = ObstacleShape::Cylinder;
  double radius_m = 0.25;                 // cylinder [m]
  double size_x_m = 1.0, size_y_m = 1.0;  // box, full lengths, x along its path [m]
  std::vector<Vec2> path;                 // at least 2 points [m]
  double speed_mps = 1.0;                 // along the path [m/s]
  double start_s = 0.0;                   // when it sets off [s]
};

struct WallSpec {
  std::vector<Vec2> points;  // polyline, at least 2 points
  double thickness_m = 0.1;
};

enum class TerrainType { Ramp, Step, Trench };

struct TerrainSpec {
  TerrainType type = TerrainType::Ramp;
  Vec2 center;
  double yaw_rad = 0.0;
  double length_m = 1.0, width_m = 1.0;
  double angle_deg = 0.0;  // ramp
  double height_m = 0.0;   // step
  // Ramp (docs/scenario-format.md): rises at angle_deg over length_m, then at angle2_deg over
  // length2_m (0: no second section), then a flat top of top_m, then (descend) down symmetrically.
  double angle2_deg = 0.0;
  double length2_m = 0.0;  // [m]
  double top_m = 0.0;      // [m]
  bool descend = true;
  double depth_m = 0.0;  // trench: how far below the floor [m], > 0
  // Length of the ground the feature covers along its own x [m] (a ramp's is more than length_m).
  double footprint_length_m() const {
    if (type != TerrainType::Ramp) return length_m;
    const double rise = length_m + length2_m;
    return (descend ? 2.0 * rise : rise) + top_m;
  }
};

// A costmap cell's label a run must end with (goto and terrain scenarios): the cell under the
// world point (x, y), read from one of the firmware's grids at the end of the run.
enum class CellLabel { Free, Passable, Lethal, Unknown };
enum class CellLayer { Master, Traversability, Obstacle };
struct CellExpect {
  Vec2 at;                            // world frame [m]
  CellLabel label = CellLabel::Free;  // free (= passable): cost 0..252; lethal: 254; unknown: 255
  CellLayer layer = CellLayer::Traversability;
  std::string what;  // what the cell is, for the message (e.g. "cube face")
};

struct ExpectSpec {
  std::optional<bool> end_reached;
  std::optional<int> max_collisions;
  std::optional<double> max_cross_track_rms_m;
  std::optional<double> min_progress;
  std::optional<int> min_laps;
  std::optional<double> max_end_stop_error_m;  // [m]
  // goto
  std::optional<bool> goal_reached;
  std::optional<double> max_goal_error_m;        // [m]
  std::optional<double> max_goal_yaw_error_deg;  // [deg]
  std::optional<std::string> fault;              // the run must end in this fault (e.g. no_path)
  std::optional<int> min_replans;                // goto: at least this many replans
  std::vector<CellExpect> cells;
  std::optional<double> min_coverage;             // coverage: swept fraction at least this
  std::optional<double> max_coverage_time_ratio;  // coverage: time / lower bound at most this
  // On a map: localisation scored against the true pose (null figures fail).
  std::optional<double> max_time_to_converge_s;   // [s]
  std::optional<double> max_relocalise_s;         // every kidnap's relocalisation time [s]
  std::optional<double> max_localisation_rmse_m;  // after convergence [m]
  bool any() const {
    return end_reached || max_collisions || max_cross_track_rms_m || min_progress || min_laps ||
           max_end_stop_error_m || goal_reached || max_goal_error_m || max_goal_yaw_error_deg ||
           fault || min_replans || !cells.empty() || min_coverage || max_coverage_time_ratio ||
           max_time_to_converge_s || max_relocalise_s || max_localisation_rmse_m;
  }
};

// The robot teleported during the run (a kidnap): at t_s it is moved to `to` (world frame).
struct KidnapSpec {
  double t_s = 0.0;  // [s]
  Pose2 to;
};

// On a scenario with a map: what the firmware is told about where it starts, and the kidnaps.
struct LocalisationSpec {
  static constexpr loader::LocalisationStartSpec kStart{};
  std::optional<Pose2> initial_pose;  // the pose the firmware is given; default the true start
  bool global = false;                // it is given none: global localisation
  // The defaults are a robot mission file's (loader::LocalisationStartSpec).
  double initial_sigma_xy_m = kStart.initial_sigma_xy_m;        // the spread round it [m]
  double initial_sigma_yaw_rad = kStart.initial_sigma_yaw_rad;  // [rad]
  bool recovery = kStart.recovery;  // augmented MCL's random injection (to recover from a kidnap)
  double max_unlocalised_s = kStart.max_unlocalised_s;  // unlocalised this long: not_localised [s]
  std::vector<KidnapSpec> kidnaps;
};

// Odometry drift: what the wheel encoders tell the firmware differs from how the body moved.
struct OdometryErrorSpec {
  // The firmware's wheel radius is off by this fraction (+0.02: it thinks the wheels 2 % larger,
  // so every distance reads 2 % long).
  double wheel_radius_error = 0.0;
  // Wheel slip: each wheel's reported speed is off by a Gaussian fraction of this standard
  // deviation, drawn afresh every 0.1 s per wheel (the heading drifts as a random walk).
  double slip = 0.0;
  bool any() const { return wheel_radius_error != 0.0 || slip != 0.0; }
};

// Worn tape (`tape_wear:`): gaps where the tape is missing, at places drawn from the scenario's
// seed, and a colour faded toward the floor's.
struct TapeWearSpec {
  double gaps_per_m = 0.0;    // mean gaps per metre of tape [1/m]
  double gap_length_m = 0.1;  // each gap's length along the tape [m]
  double fade = 0.0;          // 0: the tape's colour; 1: the floor's [-]
  bool any() const { return gaps_per_m > 0.0 || fade > 0.0; }
};

// Glare (`glare:`): a bright patch in the image, as a light's reflection on a shiny floor, that
// sweeps across the image and back once per period at a row drawn from the seed.
struct GlareSpec {
  double intensity = 0.0;   // levels added at its centre (Gaussian fall-off) [0..255]
  double radius_px = 60.0;  // the fall-off's standard deviation [px]
  double period_s = 4.0;    // one sweep across and back [s]
};

struct Scenario {
  std::string source_path;  // file it was read from
  std::string name;
  std::string description;
  double duration_s = 60.0;
  std::uint64_t seed = 0;
  Rgb floor{128, 128, 128};
  double floor_speckle = 0.15;  // the texture's shades: the floor's colour x (1 +- 1/3..1 of this)
  RobotSpec robot;
  MissionSpec mission;
  std::vector<LineSpec> lines;
  std::vector<MarkSpec> marks;
  std::vector<ObstacleSpec> obstacles;
  std::vector<MoverSpec> movers;
  std::vector<WallSpec> walls;
  std::vector<TerrainSpec> terrain;
  // Occupancy map (`map:`, docs/map-formats.md): its occupied cells are walls in the simulator,
  // and the firmware gets it as its static map. map_path is the file as resolved (relative to the
  // scenario file); empty, and map nullptr, without one. Shared: copies of a scenario do not copy
  // the cells.
  std::string map_path;
  std::shared_ptr<const loader::OccupancyMapData> map;
  LocalisationSpec localisation;
  OdometryErrorSpec odometry;
  TapeWearSpec tape_wear;
  GlareSpec glare;
  ExpectSpec expect;
};

}  // namespace carril::sim
