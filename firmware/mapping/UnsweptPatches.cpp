#include "firmware/mapping/UnsweptPatches.hpp"

#include <cstddef>

namespace carril::fw {

void unswept_patch_sizes(const std::uint8_t* mask, const std::uint8_t* counts, int nx, int ny,
                         std::uint32_t* size, std::uint32_t* queue) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  auto open = [&](std::size_t k) { return mask[k] != 0 && counts[k] == 0; };
  for (std::size_t k = 0; k < n; ++k) size[k] = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!open(k) || size[k] != 0) continue;
    // Breadth first; a queued cell is marked 1 until its patch's size is known.
    std::size_t head = 0, tail = 0;
    queue[tail++] = std::uint32_t(k);
    size[k] = 1;
    while (head < tail) {
      const std::size_t c = queue[head++];
      const int i = int(c % std::size_t(nx)), j = int(c / std::size_t(nx));
      for (int b = j - 1; b <= j + 1; ++b) {
        if (b < 0 || b >= ny) continue;
        for (int a = i - 1; a <= i + 1; ++a) {
          if (a < 0 || a >= nx) continue;
          const std::size_t q = std::size_t(b) * std::size_t(nx) + std::size_t(a);
          if (size[q] != 0 || !open(q)) continue;
          size[q] = 1;
          queue[tail++] = std::uint32_t(q);
        }
      }
    }
    for (std::size_t q = 0; q < tail; ++q) size[queue[q]] = std::uint32_t(tail);
  }
}

}  // namespace carril::fw
