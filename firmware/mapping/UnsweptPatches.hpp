#pragma once
// What a cleaning run has left, as patches: the 8-connected sets of cells inside the area's mask
// that the tool has not swept yet (count 0). The coverage mission goes back only for patches
// large enough to be worth the trip. O(cells), no allocation: the caller sizes the buffers.
#include <cstdint>

namespace carril::fw {

// size[k] = the number of cells of k's patch for every cell with mask[k] != 0 and counts[k] == 0,
// else 0 [cells]. Grids of nx * ny cells, row-major; queue is nx * ny cells of scratch.
void unswept_patch_sizes(const std::uint8_t* mask, const std::uint8_t* counts, int nx, int ny,
                         std::uint32_t* size, std::uint32_t* queue);

}  // namespace carril::fw
