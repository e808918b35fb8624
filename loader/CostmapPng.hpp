#pragma once
// A costmap as a colour PNG, for documentation and reports (host only: library
// carril_costmap_png, which links libpng; the robot build has no libpng).
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "loader/CostmapExport.hpp"

namespace carril::loader {

// The colour of a cost (R, G, B): free white, graded light yellow to dark orange, inscribed
// orange-red, lethal black, unknown mid grey.
std::array<std::uint8_t, 3> costmap_png_rgb(std::uint8_t cost);

// Writes `path` (8-bit RGB PNG, top row = highest y like the PGM), each cell `scale` x `scale`
// pixels (1 to 16), atomically. nullopt on success, else a message naming the file.
std::optional<std::string> export_costmap_png(const std::string& path, const std::uint8_t* costs,
                                              const CostmapGeometry& geometry, int scale = 1);

}  // namespace carril::loader
