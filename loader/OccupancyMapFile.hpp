#pragma once
// Occupancy maps in ROS map_server's format (docs/map-formats.md): a YAML file (image,
// resolution, origin, negate, occupied_thresh, free_thresh, mode) naming a PGM image, read in
// trinary mode into the cost values fw::OccupancyGrid::assign takes. Strict like every carril
// file: an unknown, missing or mistyped key, a broken image or a map bigger than the buffer it
// fills is one error naming the YAML file, the key and (for the image) the PGM file.
// Host and robot side (init time, not in a tick): it allocates and reads files.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::loader {

// Largest image file read at all, checked before anything is allocated for it [bytes]: a
// 1000 x 1000 map is 1 MB as P5 and about 4 MB as P2.
inline constexpr std::size_t kMaxMapImageBytes = std::size_t{64} << 20;
// Cells of a map a target loads (1000 x 1000: 50 x 50 m at 5 cm); the firmware's static map
// buffer is sized to the map it is given.
inline constexpr std::size_t kMaxMapCells = 1'000'000;
// Longest side of an image [pixels] (MapInfo counts cells in int).
inline constexpr std::uint64_t kMaxMapImageSide = 1U << 20;

// A loaded map: cells row-major from the lower-left cell (cell (i, j) is cells[j * nx + i]; the
// image's top row is the map's highest y), each fw::cost::kFree, kLethal or kUnknown.
struct OccupancyMapData {
  fw::MapInfo info;                 // size, resolution [m], origin of cell (0, 0)'s corner [m]
  std::vector<std::uint8_t> cells;  // info.nx * info.ny cost values
  std::string image_path;           // the PGM file as resolved from the YAML's `image`
};

// Result of load_occupancy_map: the map, or (error non-empty) one message naming the file.
struct OccupancyMapLoad {
  OccupancyMapData map;
  std::string error;
  bool ok() const { return error.empty(); }
};

// Loads the map_server YAML at `yaml_path` and its image (relative to the YAML's folder, or
// absolute), refusing a map of more than `max_cells` cells (the buffer it will fill).
// Trinary mode as map_server: p = (maxval - v) / maxval (v / maxval with negate: 1);
// p > occupied_thresh is occupied, p < free_thresh free, anything else unknown.
OccupancyMapLoad load_occupancy_map(const std::string& yaml_path, std::size_t max_cells);

// Writes `map` as BASE.pgm + BASE.yaml (loader/CostmapExport.hpp's format: free 254, occupied 0,
// unknown 205, trinary thresholds 0.65 / 0.196), which load_occupancy_map reads back exactly.
// nullopt on success, else a message naming the file.
std::optional<std::string> save_occupancy_map(const std::string& base_path,
                                              const OccupancyMapData& map);

}  // namespace carril::loader
