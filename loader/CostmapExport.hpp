#pragma once
// Costmaps (fw::cost values, Nav2 semantics) as files other tools read: a PGM + YAML pair in the
// ROS map_server convention, for RViz, map_server and Nav2. Layout of the costs: nx * ny bytes,
// row-major from the lower-left cell (cell (i, j) is costs[j * nx + i]), the firmware's grids'
// order. Host and robot side (not in a tick): it allocates and writes files.
// docs/map-formats.md describes both files and the grey levels.
#include <cstdint>
#include <optional>
#include <string>

namespace carril::loader {

// Geometry of an exported costmap.
struct CostmapGeometry {
  std::uint32_t nx = 0, ny = 0;  // cells along x and y
  double resolution_m = 0.0;     // cell side [m]
  double origin_x_m = 0.0;       // world x of the lower-left corner of cell (0, 0) [m]
  double origin_y_m = 0.0;       // world y of that corner [m]
};

// The PGM grey of a cost: free 254 (white), graded 253..206 (light greys that map_server's
// trinary mode still reads as free, since a graded cell is passable), unknown 205, inscribed and
// lethal 0 (black, occupied).
std::uint8_t costmap_pgm_grey(std::uint8_t cost);

// Writes BASE.pgm (binary P5, 8 bit, top row = highest y) and BASE.yaml (image: BASE.pgm
// relative, resolution, origin [x, y, 0.0], negate 0, occupied_thresh 0.65, free_thresh 0.196,
// mode trinary), each atomically, the image first. nullopt on success, else a message naming the
// file.
std::optional<std::string> export_costmap_pgm(const std::string& base_path,
                                              const std::uint8_t* costs,
                                              const CostmapGeometry& geometry);

}  // namespace carril::loader
