#include "firmware/mapping/GridRay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

namespace carril::fw {
namespace {

// The walk trace_line made before it ran in wrap-free pieces (a wrap test on both coordinates
// every step), kept as the reference its cell sequence must match exactly: the costmap's grids
// and the simulator's trajectories depend on which cells a ray clears.
std::vector<std::size_t> reference_trace(int cx0, int cy0, int cx1, int cy1, int nx, int ny,
                                         bool include_end) {
  std::vector<std::size_t> out;
  const int adx = std::abs(cx1 - cx0), ady = std::abs(cy1 - cy0);
  const int sx = cx1 >= cx0 ? 1 : -1, sy = cy1 >= cy0 ? 1 : -1;
  int col = grid::wrap(cx0, nx), row = grid::wrap(cy0, ny);
  const bool x_major = adx >= ady;
  const int da = x_major ? adx : ady, db = x_major ? ady : adx;
  int steps = include_end ? da + 1 : da;
  int err = da / 2;
  const auto step = [](int& v, int s, int n) {
    v += s;
    if (v == n) v = 0;
    if (v < 0) v = n - 1;
  };
  while (steps-- > 0) {
    out.push_back(std::size_t(row) * std::size_t(nx) + std::size_t(col));
    if (x_major) {
      step(col, sx, nx);
    } else {
      step(row, sy, ny);
    }
    err -= db;
    if (err < 0) {
      err += da;
      if (x_major) {
        step(row, sy, ny);
      } else {
        step(col, sx, nx);
      }
    }
  }
  return out;
}

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

TEST(GridRayTest, PiecewiseWalkVisitsTheReferenceCellsInOrder) {
  // Windows whose storage wraps inside them in both axes (and one that does not), of odd and
  // even sizes, down to one cell wide; random rays between any two cells of the window.
  struct Window {
    int nx, ny, ox, oy;
  };
  const Window windows[] = {{16, 12, -20, 5},
                            {240, 240, 1234, -517},
                            {7, 9, 3, -4},
                            {1, 5, -3, 2},
                            {6, 1, 4, 8},
                            {33, 17, 0, 0},
                            {240, 240, -119, 61},
                            // Rays longer than the closed-form walk takes (grid::
                            // kClosedFormMaxSteps) step the error instead: both kinds.
                            {4200, 4150, -2100, 17},
                            {5000, 40, 3, -9}};
  std::mt19937 rng(42);
  int octants[8] = {};
  int rays = 0, zero_length = 0, wrapped = 0;
  for (const Window& w : windows) {
    std::uniform_int_distribution<int> px(w.ox, w.ox + w.nx - 1), py(w.oy, w.oy + w.ny - 1);
    for (int r = 0; r < 4000; ++r) {
      const int x0 = px(rng), y0 = py(rng);
      // A few rays of length zero, and many that are short.
      int x1 = px(rng), y1 = py(rng);
      if (r % 50 == 0) x1 = x0, y1 = y0;
      if (r % 3 == 0) {
        x1 = std::clamp(x0 + (x1 - x0) / 8, w.ox, w.ox + w.nx - 1);
        y1 = std::clamp(y0 + (y1 - y0) / 8, w.oy, w.oy + w.ny - 1);
      }
      for (const bool include_end : {false, true}) {
        std::vector<std::size_t> got;
        grid::trace_line(x0, y0, x1, y1, w.nx, w.ny, include_end,
                         [&](std::size_t i) { got.push_back(i); });
        const auto want = reference_trace(x0, y0, x1, y1, w.nx, w.ny, include_end);
        ASSERT_EQ(got, want) << "window " << w.nx << "x" << w.ny << " at (" << w.ox << ", " << w.oy
                             << "), ray (" << x0 << ", " << y0 << ") -> (" << x1 << ", " << y1
                             << "), include_end " << include_end;
        ++rays;
      }
      const int dx = x1 - x0, dy = y1 - y0;
      if (dx == 0 && dy == 0) {
        ++zero_length;
        continue;
      }
      // Octant: sign of x, sign of y, which axis is major.
      ++octants[(dx < 0 ? 4 : 0) + (dy < 0 ? 2 : 0) + (std::abs(dx) >= std::abs(dy) ? 1 : 0)];
      if (grid::wrap(x0, w.nx) + dx != grid::wrap(x1, w.nx) &&
          grid::wrap(y0, w.ny) + dy != grid::wrap(y1, w.ny)) {
        ++wrapped;  // crosses both a column and a row wrap
      }
    }
  }
  // The sample covers what it should.
  for (int o = 0; o < 8; ++o) EXPECT_GT(octants[o], 100) << "octant " << o;
  EXPECT_GT(zero_length, 100);
  EXPECT_GT(wrapped, 1000);
  EXPECT_EQ(rays, 2 * 4000 * int(std::size(windows)));
}

// A walk told to skip its first s steps visits the reference cells from the (s+1)-th on, in
// order, across storage wraps (the skip may end in any of the walk's pieces) and when s is as
// long as the ray or longer.
TEST(GridRayTest, SkippedStepsLeaveOutExactlyTheFirstCells) {
  struct Window {
    int nx, ny, ox, oy;
  };
  // The last window has rays longer than the closed-form walk takes.
  const Window windows[] = {
      {16, 12, -20, 5}, {240, 240, 1234, -517}, {7, 9, 3, -4}, {33, 17, 0, 0}, {5000, 40, 3, -9}};
  std::mt19937 rng(7);
  int rays = 0, skipped_into_a_later_piece = 0;
  for (const Window& w : windows) {
    std::uniform_int_distribution<int> px(w.ox, w.ox + w.nx - 1), py(w.oy, w.oy + w.ny - 1);
    for (int r = 0; r < 3000; ++r) {
      const int x0 = px(rng), y0 = py(rng), x1 = px(rng), y1 = py(rng);
      const bool include_end = r % 2 == 0;
      const auto want = reference_trace(x0, y0, x1, y1, w.nx, w.ny, include_end);
      const int n = int(want.size());
      const int skip = std::uniform_int_distribution<int>(0, n + 2)(rng);
      std::vector<std::size_t> got;
      grid::trace_line_from(
          grid::wrap(x0, w.nx), grid::wrap(y0, w.ny), x1 - x0, y1 - y0, w.nx, w.ny, include_end,
          [&](std::size_t i) { got.push_back(i); }, skip);
      const std::vector<std::size_t> tail(want.begin() + std::min(skip, n), want.end());
      ASSERT_EQ(got, tail) << "window " << w.nx << "x" << w.ny << ", ray (" << x0 << ", " << y0
                           << ") -> (" << x1 << ", " << y1 << "), skip " << skip;
      // The skip crossed a storage wrap: a cell it left out and the first one visited are
      // not one major step apart in storage.
      if (skip > 0 && skip < n) {
        const auto col = [&](std::size_t i) { return int(i % std::size_t(w.nx)); };
        const auto row = [&](std::size_t i) { return int(i / std::size_t(w.nx)); };
        const int dc = std::abs(col(want[0]) - col(want[std::size_t(skip)]));
        const int dr = std::abs(row(want[0]) - row(want[std::size_t(skip)]));
        if (std::max(dc, dr) != skip) ++skipped_into_a_later_piece;
      }
      ++rays;
    }
  }
  EXPECT_EQ(rays, 5 * 3000);
  EXPECT_GT(skipped_into_a_later_piece, 500);
}

TEST(GridRayTest, ClosedFormWalkMatchesTheReferenceForEveryLengthItTakes) {
  // Every major-axis length up to grid::kClosedFormMaxSteps and one past it, with minor lengths
  // from flat to diagonal, in all four directions: the reciprocal that replaces the division
  // must give Bresenham's cells exactly (the largest numerators come with the longest rays).
  constexpr int n = 8192;  // a window larger than every ray: no wraps, only the walk itself
  std::vector<int> lengths;
  for (int da = 1; da < grid::kClosedFormMaxSteps - 1; da += (da < 300 ? 1 : 97)) {
    lengths.push_back(da);
  }
  for (int k = -1; k <= 1; ++k) lengths.push_back(grid::kClosedFormMaxSteps + k);
  int lines = 0, longest = 0;
  for (const int da : lengths) {
    longest = std::max(longest, da);
    for (const int db : {0, 1, da / 3, da / 2, da - 1, da}) {
      for (const int dir : {0, 1, 2, 3}) {
        const int sa = dir & 1 ? -1 : 1, sb = dir & 2 ? -1 : 1;
        const int x1 = 4096 + sa * da, y1 = 4096 + sb * db;
        std::vector<std::size_t> got;
        grid::trace_line(4096, 4096, x1, y1, n, n, true, [&](std::size_t i) { got.push_back(i); });
        ASSERT_EQ(got, reference_trace(4096, 4096, x1, y1, n, n, true))
            << "da " << da << " db " << db << " direction " << dir;
        // And y-major: the same line transposed.
        got.clear();
        grid::trace_line(4096, 4096, y1, x1, n, n, true, [&](std::size_t i) { got.push_back(i); });
        ASSERT_EQ(got, reference_trace(4096, 4096, y1, x1, n, n, true))
            << "transposed, da " << da << " db " << db << " direction " << dir;
        lines += 2;
      }
    }
  }
  EXPECT_GT(lines, 15000);
  EXPECT_EQ(longest, grid::kClosedFormMaxSteps + 1);
}

// A window cell's storage column from the window's offset equals the modulo storage_index
// takes, for windows anywhere (negative origins included) and every cell in them.
TEST(GridRayTest, WindowStorageEqualsTheModuloForEveryCellOfTheWindow) {
  int cells = 0;
  for (const int n : {1, 2, 7, 64, 161}) {
    for (const int lo : {-1000, -161, -65, -1, 0, 1, 63, 64, 999}) {
      for (int c = lo; c < lo + n; ++c) {
        ASSERT_EQ(grid::window_storage(c, lo, grid::wrap(lo, n), n), grid::wrap(c, n))
            << "n " << n << " lo " << lo << " c " << c;
        ++cells;
      }
    }
  }
  EXPECT_EQ(cells, 9 * (1 + 2 + 7 + 64 + 161));
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

// clip_segment's shortcut for a segment inside the box gives clip_segment_any's values to the bit:
// the ray's cells depend on them. Ends on the box's edges and corners, one ulp inside and outside,
// and farther out (the loop's case) are among the draws.
TEST(GridRayTest, ClipOfASegmentInsideGivesTheLoopsValuesToTheBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> in_x(-3.7, 8.3), in_y(-1.1, 5.9);
  const double xmin = -3.7, ymin = -1.1, xmax = 8.3, ymax = 5.9;
  const auto pick = [&](std::uniform_real_distribution<double>& d, double lo, double hi) {
    switch (rng() % 7) {
      case 0:
        return lo;
      case 1:
        return hi;
      case 2:
        return std::nextafter(hi, lo);
      case 3:
        return std::nextafter(lo, lo - 1.0);  // just outside: the loop's case
      case 4:
        return d(rng) + (hi - lo) * 0.5;  // maybe outside
      default:
        return d(rng);
    }
  };
  int moved_end = 0;
  for (int k = 0; k < 200000; ++k) {
    double a[4] = {pick(in_x, xmin, xmax), pick(in_y, ymin, ymax), pick(in_x, xmin, xmax),
                   pick(in_y, ymin, ymax)};
    double b[4] = {a[0], a[1], a[2], a[3]};
    const double x1_in = a[2], y1_in = a[3];
    bool ea = true, eb = true;
    const bool ra = grid::clip_segment(a[0], a[1], a[2], a[3], xmin, ymin, xmax, ymax, ea);
    const bool rb = grid::clip_segment_any(b[0], b[1], b[2], b[3], xmin, ymin, xmax, ymax, eb);
    ASSERT_EQ(ra, rb) << k;
    ASSERT_EQ(ea, eb) << k;
    for (int i = 0; i < 4; ++i) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(a[i]), std::bit_cast<std::uint64_t>(b[i]))
          << "draw " << k << " value " << i;
    }
    // x0 + (x1 - x0) is not always x1: the draws must include ends the loop moves by an ulp,
    // or a shortcut that kept the ends as given would pass.
    if (b[2] != x1_in || b[3] != y1_in) ++moved_end;
  }
  EXPECT_GT(moved_end, 1000);
}

}  // namespace
}  // namespace carril::fw
