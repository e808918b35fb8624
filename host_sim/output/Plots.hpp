#pragma once
// The run's two plots, rendered to PNG bytes in memory (the caller writes them atomically):
// a top view of the scenario with the robot's path, and its velocities against time.
#include <string>
#include <vector>

#include "host_sim/output/RunOutputs.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// Top view, y up: floor, terrain, walls, tape, marks, obstacles, the path coloured by behaviour
// state (with a legend), collisions, start, a 1 m scale bar and a title line.
bool render_trajectory_png(const Scenario& scenario, const std::vector<TrajectoryRow>& rows,
                           const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                           std::string& png, std::string& error);

// vx, vy [m/s] and wz [rad/s] against t, three stacked panels; a "no data" note when empty.
bool render_velocities_png(const std::vector<TrajectoryRow>& rows, const RunSummary& summary,
                           std::string& png, std::string& error);

}  // namespace carril::sim
