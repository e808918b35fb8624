#pragma once
// A mission on a known map, for every target alike (carril_sim and carril_controller): the map
// frame becomes the mission's frame, the firmware localises on the map with Monte Carlo
// localisation from the given start, and the costmap covers the map with no terrain layer. The
// map's cells themselves (fw::FirmwareConfig::map) are owned and set by the target's wiring file.
#include "firmware/app/FirmwareConfig.hpp"
#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::loader {

// Sets `c` (built by build_firmware_config) up for a map: localisation from `start` (its
// initial_pose, else `default_pose` [m, m, rad]), the lidar's mount and range from `robot`, random
// injection only when start.recovery (AMCL's defaults leave it off), and no terrain layer.
void configure_for_map(const RobotSpec& robot, const LocalisationStartSpec& start,
                       const fw::Pose2& default_pose, fw::FirmwareConfig& c);

}  // namespace carril::loader
