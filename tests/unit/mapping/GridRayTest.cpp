#include "firmware/mapping/GridRay.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

namespace carril::fw {
namespace {

struct Cell {
  int cx, cy;
};

// The global cells a traced line visits, recovered from storage indices of a window whose
// origin is (ox, oy).
std::vector<Cell> trace(int x0, int y0, int x1, int y1, bool include_end, int ox, int oy) {
  constexpr int nx = 16, ny = 12;
  std::vector<std::size_t> idx;
  grid::trace_line(x0, y0, x1, y1, nx, ny, include_end, [&](std::size_t i) { idx.push_back(i); });
  std::vector<Cell> cells;
  for (std::size_t i : idx) {
    const int sx = int(i % nx), sy = int(i / nx);
    // The global cell in [ox, ox + nx) with that storage column (and the same for rows).
    const int cx = ox + grid::wrap(sx - ox, nx), cy = oy + grid::wrap(sy - oy, ny);
    cells.push_back({cx, cy});
  }
  return cells;
}

TEST(GridRayTest, LinesRunFromStartToEndOneStepAtATime) {
  // Window [-20, -4) x [5, 17): storage wraps inside it.
  const int ox = -20, oy = 5;
  const int ends[][4] = {{-19, 6, -6, 15},  {-6, 15, -19, 6}, {-10, 6, -10, 16},
                         {-5, 10, -20, 10}, {-12, 8, -7, 9},  {-15, 16, -16, 5}};
  for (const auto& e : ends) {
    const auto cells = trace(e[0], e[1], e[2], e[3], true, ox, oy);
    const int n = std::max(std::abs(e[2] - e[0]), std::abs(e[3] - e[1])) + 1;
    ASSERT_EQ(int(cells.size()), n);
    EXPECT_EQ(cells.front().cx, e[0]);
    EXPECT_EQ(cells.front().cy, e[1]);
    EXPECT_EQ(cells.back().cx, e[2]);
    EXPECT_EQ(cells.back().cy, e[3]);
    for (std::size_t k = 1; k < cells.size(); ++k) {
      EXPECT_LE(std::abs(cells[k].cx - cells[k - 1].cx), 1);
      EXPECT_LE(std::abs(cells[k].cy - cells[k - 1].cy), 1);
    }
    // Without the end cell: the same line minus its last cell.
    const auto open = trace(e[0], e[1], e[2], e[3], false, ox, oy);
    ASSERT_EQ(open.size(), cells.size() - 1);
    EXPECT_EQ(open.back().cx, cells[cells.size() - 2].cx);
    EXPECT_EQ(open.back().cy, cells[cells.size() - 2].cy);
  }
  EXPECT_TRUE(trace(-8, 7, -8, 7, false, ox, oy).empty());
  EXPECT_EQ(trace(-8, 7, -8, 7, true, ox, oy).size(), 1U);
}

TEST(GridRayTest, ClipKeepsThePartInsideTheBox) {
  double x0 = -1.0, y0 = 0.5, x1 = 3.0, y1 = 0.5;
  bool end_clipped = false;
  ASSERT_TRUE(grid::clip_segment(x0, y0, x1, y1, 0.0, 0.0, 2.0, 1.0, end_clipped));
  EXPECT_DOUBLE_EQ(x0, 0.0);
  EXPECT_DOUBLE_EQ(x1, 2.0);
  EXPECT_TRUE(end_clipped);
  x0 = 0.5, y0 = 0.5, x1 = 1.5, y1 = 0.7;
  ASSERT_TRUE(grid::clip_segment(x0, y0, x1, y1, 0.0, 0.0, 2.0, 1.0, end_clipped));
  EXPECT_FALSE(end_clipped);
  EXPECT_DOUBLE_EQ(x1, 1.5);
  x0 = -1.0, y0 = 2.0, x1 = 3.0, y1 = 2.5;  // above the box
  EXPECT_FALSE(grid::clip_segment(x0, y0, x1, y1, 0.0, 0.0, 2.0, 1.0, end_clipped));
}

}  // namespace
}  // namespace carril::fw
