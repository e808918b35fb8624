#pragma once
// Saved elevation maps (docs/map-formats.md): the elevation layer, not a costmap, so that another
// robot profile can derive its own costmap from the same survey. A versioned little-endian binary
// file with a CRC-32, read field by field so any platform reads what another wrote.
// Host and robot side (init time, not in a tick): it allocates, reads and writes files.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "firmware/mapping/ElevationCell.hpp"

namespace carril::loader {

// The format as this build writes and reads it.
inline constexpr char kElevationMapMagic[8] = {'C', 'A', 'R', 'R', 'I', 'L', 'E', 'M'};
inline constexpr std::uint32_t kElevationMapVersion = 1;
inline constexpr std::size_t kElevationMapFrameBytes = 32;  // frame name, NUL padded
inline constexpr std::size_t kElevationMapHeaderBytes = 84;
inline constexpr std::size_t kElevationMapCellBytes = 8;  // float height, float variance
inline constexpr std::size_t kElevationMapCrcBytes = 4;

// An elevation map in memory: nx * ny cells, row-major from the lower-left cell (cell (i, j) is
// cells[j * nx + i], centred at origin + ((i + 0.5) * resolution, (j + 0.5) * resolution)).
struct ElevationMapData {
  double resolution_m = 0.0;             // cell side [m]
  std::uint32_t nx = 0, ny = 0;          // cells along x and y
  double origin_x_m = 0.0;               // world x of the lower-left corner of cell (0, 0) [m]
  double origin_y_m = 0.0;               // world y of that corner [m]
  std::string frame = "odom";            // frame of the heights and the origin (<= 31 chars)
  std::vector<fw::ElevationCell> cells;  // nx * ny; variance 0 = never observed
};

// Result of load_elevation_map: the map, or (error non-empty) a message naming the file.
struct ElevationMapLoad {
  ElevationMapData map;
  std::string error;
  bool ok() const { return error.empty(); }
};

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, as zlib's crc32) of `n` bytes, continuing
// from `crc` (0 to start).
std::uint32_t crc32_ieee(const void* data, std::size_t n, std::uint32_t crc = 0);

// The file's bytes for `map` (header, cells, CRC); nullopt and `error` when the map is invalid.
std::optional<std::string> encode_elevation_map(const ElevationMapData& map, std::string& error);

// Saves `map` to `path` atomically (temporary file, fsync, rename, fsync of the directory).
// nullopt on success, else a message naming the path (and the errno text for I/O errors).
std::optional<std::string> save_elevation_map(const std::string& path, const ElevationMapData& map);

// Loads the map at `path`, refusing maps of more than `max_cells` cells (the grid it will fill).
// Errors name the file and what is wrong: missing, truncated, not a carril map, other version,
// CRC mismatch, inconsistent sizes, non-finite numbers, too big.
ElevationMapLoad load_elevation_map(const std::string& path, std::uint64_t max_cells);

}  // namespace carril::loader
