#pragma once
// The blocks of a robot description, for loaders that read them inside another file (a
// scenario's `robot:` overrides). Internal to the loaders: throws strict::LoadError.
#include <string>

#include "loader/RobotSpec.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::loader {

// Each reads its block into the spec. `all`: a robot file, where every key is required (the
// lidar's `present` is optional, and with `present: false` so are the others); otherwise a
// partial override, where every key is optional and `present` is not allowed.
void parse_camera(const strict::Node& m, CameraSpec& c, bool all);
void parse_lidar(const strict::Node& m, LidarSpec& l, bool all);
// `lidar3d:` (with `all`, `present` is optional, true when the block is there).
void parse_lidar3d(const strict::Node& m, Lidar3dSpec& l, bool all);
void parse_limits(const strict::Node& m, LimitsSpec& l, bool all);
void parse_traversability(const strict::Node& m, TraversabilitySpec& t, bool all);
void parse_terrain_limits(const strict::Node& m, TerrainLimitsSpec& t, bool all);

// The camera must see the floor: every image row below the horizon and the image centre on the
// floor within 20 m. Reported on `where`.tilt_deg (`where` is the block that set the values).
void check_camera_view(const strict::Node& where, const CameraSpec& c);

// Reads and checks a whole robot description file.
RobotSpec read_robot_file(const std::string& path);

}  // namespace carril::loader
