#pragma once
// What a run with a costmap adds to its outputs and its score: the goal's figures (goto), the
// labels of the cells a scenario expects, and the maps as images (costmap.png, traversability.png,
// obstacles.png, the map_server pair costmap.pgm + costmap.yaml) and the saved elevation map
// (elevation.cmap) from which another robot profile can derive its own costmap.
#include <string>

#include "firmware/app/Firmware.hpp"
#include "host_sim/output/RunOutputs.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// A world point in the firmware's odometry frame (its origin is the start pose).
fw::Pose2 world_to_odom(const Pose2& start, double x, double y, double yaw_rad);

// goal_reached, goal_error_m, goal_yaw_error_deg and replans of a goto run, from the true pose.
void score_goto(const Scenario& s, const fw::Firmware& firmware, const Pose2& true_pose,
                RunSummary& r);

// Checks every expect.cells entry against the firmware's grids at the end of the run; a miss
// names the cell, what it is, the label expected and the cost found.
void check_cells(const Scenario& s, const fw::Firmware& firmware, RunSummary& r);

// Writes the map files into `dir` (nothing when the firmware builds no costmap); with `pngs`
// false only the data files (costmap.pgm/.yaml, elevation.cmap), no images.
bool write_costmap_outputs(const fw::Firmware& firmware, const std::string& dir, std::string& error,
                           bool pngs = true);

}  // namespace carril::sim
