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

// Writes the image (binary P5, 8 bit, top row = highest y) and BASE.yaml (image relative,
// resolution, origin [x, y, 0.0], negate 0, occupied_thresh 0.65, free_thresh 0.196, mode
// trinary), each atomically, the image first. A kill at any moment leaves the old pair or the new
// one: the image is BASE.pgm, or BASE.next.pgm when the YAML being replaced uses BASE.pgm (they
// alternate), the YAML's rename switches pairs, the old image is removed after; temporaries of
// an export that was killed are removed by the next. nullopt on success, else a message naming
// the file.
std::optional<std::string> export_costmap_pgm(const std::string& base_path,
                                              const std::uint8_t* costs,
                                              const CostmapGeometry& geometry);

// The two steps of export_costmap_pgm(), apart so that a test can stop between them as a kill
// would: the image under the name the current YAML does not use, then the YAML that switches.
struct CostmapImageStep {
  std::string image_path;      // where the new image went
  std::string old_image_path;  // the current YAML's image, removed once the new YAML is in
  bool had_yaml = false;       // a YAML was there before
};
std::optional<std::string> write_costmap_image(const std::string& base_path,
                                               const std::uint8_t* costs,
                                               const CostmapGeometry& geometry,
                                               CostmapImageStep& step);
std::optional<std::string> commit_costmap_yaml(const std::string& base_path,
                                               const CostmapGeometry& geometry,
                                               const CostmapImageStep& step);

}  // namespace carril::loader
