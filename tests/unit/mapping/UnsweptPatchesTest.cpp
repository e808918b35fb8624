// unswept_patch_sizes against a union-find over the same grid (8-connected), on hand-made and
// random grids.
#include "firmware/mapping/UnsweptPatches.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

namespace carril::fw {
namespace {

// The reference: union-find over every pair of open 8-neighbours, then the set sizes.
std::vector<std::uint32_t> reference(const std::vector<std::uint8_t>& mask,
                                     const std::vector<std::uint8_t>& counts, int nx, int ny) {
  const std::size_t n = mask.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  auto open = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= nx || j >= ny) return false;
    const std::size_t k = std::size_t(j * nx + i);
    return mask[k] != 0 && counts[k] == 0;
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (!open(i, j)) continue;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          if (open(i + di, j + dj)) {
            parent[find(std::size_t(j * nx + i))] = find(std::size_t((j + dj) * nx + i + di));
          }
        }
      }
    }
  }
  std::vector<std::uint32_t> count(n, 0), out(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    if (mask[k] != 0 && counts[k] == 0) ++count[find(k)];
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (mask[k] != 0 && counts[k] == 0) out[k] = count[find(k)];
  }
  return out;
}

std::vector<std::uint32_t> sizes(const std::vector<std::uint8_t>& mask,
                                 const std::vector<std::uint8_t>& counts, int nx, int ny) {
  std::vector<std::uint32_t> size(mask.size(), 7u), queue(mask.size(), 0u);
  unswept_patch_sizes(mask.data(), counts.data(), nx, ny, size.data(), queue.data());
  return size;
}

// Diagonal neighbours join a patch; swept cells and cells off the mask split them; neither
// gets a size.
TEST(UnsweptPatchesTest, DiagonalsJoinSweptCellsAndTheMaskSplit) {
  const int nx = 5, ny = 3;
  // mask row-major from the bottom row; counts: 1 = swept
  const std::vector<std::uint8_t> mask = {1, 1, 1, 1, 1,  //
                                          1, 1, 1, 0, 1,  //
                                          1, 1, 1, 1, 1};
  const std::vector<std::uint8_t> counts = {0, 2, 1, 1, 0,  //
                                            1, 0, 1, 0, 1,  //
                                            1, 1, 1, 0, 0};
  const std::vector<std::uint32_t> want = {2, 0, 0, 0, 1,  //
                                           0, 2, 0, 0, 0,  //
                                           0, 0, 0, 2, 2};
  EXPECT_EQ(sizes(mask, counts, nx, ny), want);
}

TEST(UnsweptPatchesTest, RandomGridsMatchAUnionFind) {
  std::mt19937 rng(11);
  for (int t = 0; t < 300; ++t) {
    const int nx = 1 + int(rng() % 60), ny = 1 + int(rng() % 40);
    const double p_mask = 0.5 + 0.5 * double(rng() % 100) / 100.0;
    const double p_swept = double(rng() % 100) / 100.0;
    std::vector<std::uint8_t> mask(std::size_t(nx * ny)), counts(std::size_t(nx * ny));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t k = 0; k < mask.size(); ++k) {
      mask[k] = u(rng) < p_mask ? 1 : 0;
      counts[k] = u(rng) < p_swept ? std::uint8_t(1 + rng() % 3) : 0;
    }
    ASSERT_EQ(sizes(mask, counts, nx, ny), reference(mask, counts, nx, ny))
        << "grid " << t << ": " << nx << " x " << ny;
  }
}

}  // namespace
}  // namespace carril::fw
