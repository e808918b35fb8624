#pragma once
// Simulator walls from an occupancy map (a scenario's `map:`): the occupied cells merged into few
// axis-aligned rectangles, built into the Box2D world as one static body, so the 2D lidar's ray
// casts and the robot's contacts see the map as the firmware's static layer does.
#include <box2d/box2d.h>

#include <vector>

#include "loader/OccupancyMapFile.hpp"

namespace carril::sim {

// A rectangle of occupied cells: cells i0..i1-1 along x, j0..j1-1 along y, and its world extent.
struct WallRect {
  int i0 = 0, j0 = 0, i1 = 0, j1 = 0;  // half-open cell ranges
  double min_x = 0.0, min_y = 0.0;     // world lower-left corner [m]
  double max_x = 0.0, max_y = 0.0;     // world upper-right corner [m]
};

// Rectangles covering every occupied (fw::cost::kLethal) cell of `map` exactly once and no other
// cell: runs of occupied cells merged across rows (and across columns; the fewer of the two).
std::vector<WallRect> merge_occupied_cells(const loader::OccupancyMapData& map);

// Adds `rects` to `world` as one static body with one box fixture per rectangle; the body
// (nullptr when there is none).
b2Body* add_map_walls(b2World& world, const std::vector<WallRect>& rects);

}  // namespace carril::sim
