#pragma once
// Integer ray tracing over a RollingGrid's storage, and the clipping that keeps rays inside the
// window. Rays walk global cell indices with Bresenham (one cell per step along the major axis,
// as Nav2's raytraceLine): fewer cells than an exact supercover walk, so a beam grazing a wall
// does not clear the wall's corner cells. Steps add a stride to a linear storage index, with the
// storage wraps handled between pieces of the ray, so a 120-cell ray costs about as much as 120
// array writes.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "firmware/core/RollingGrid.hpp"

namespace carril::fw::grid {

// a mod n in [0, n) for any sign of a.
inline int wrap(int a, int n) {
  const int m = a % n;
  return m < 0 ? m + n : m;
}

// Storage index of the global cell (cx, cy) in any RollingGrid of nx x ny cells (RollingGrid
// stores world cell (cx, cy) at storage (cx mod nx, cy mod ny), row-major).
inline std::size_t storage_index(int cx, int cy, int nx, int ny) {
  return std::size_t(wrap(cy, ny)) * std::size_t(nx) + std::size_t(wrap(cx, nx));
}

// Storage column (or row) of global cell c in a window whose first cell, lo, is stored at off
// (RollingGrid::column_offset() / row_offset(), n cells across): for c inside the window,
// off + (c - lo) less one wrap at most, with no division.
inline int window_storage(int c, int lo, int off, int n) {
  const int v = off + (c - lo);
  return v >= n ? v - n : v;
}

// The first element of a grid's storage (nx * ny cells, row-major). Grids of equal size and
// origin share storage indices, which lets layers be combined element by element.
template <typename T>
T* storage_base(RollingGrid<T>& g) {
  const int cx = g.origin_cx(), cy = g.origin_cy();
  return &g.at(cx, cy) - storage_index(cx, cy, g.nx(), g.ny());
}
template <typename T>
const T* storage_base(const RollingGrid<T>& g) {
  const int cx = g.origin_cx(), cy = g.origin_cy();
  return &g.at(cx, cy) - storage_index(cx, cy, g.nx(), g.ny());
}

// True when two grids cover the same cells with the same storage layout.
template <typename A, typename B>
bool same_window(const RollingGrid<A>& a, const RollingGrid<B>& b) {
  return a.nx() == b.nx() && a.ny() == b.ny() && a.origin_cx() == b.origin_cx() &&
         a.origin_cy() == b.origin_cy() && a.resolution() == b.resolution();
}

// Clips the segment (x0, y0) -> (x1, y1) [m] to the box [xmin, xmax] x [ymin, ymax]
// (Liang-Barsky), whatever the ends. false when nothing of it is inside. end_clipped tells whether
// (x1, y1) moved.
inline bool clip_segment_any(double& x0, double& y0, double& x1, double& y1, double xmin,
                             double ymin, double xmax, double ymax, bool& end_clipped) {
  const double dx = x1 - x0, dy = y1 - y0;
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {x0 - xmin, xmax - x0, y0 - ymin, ymax - y0};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;  // parallel to this edge and outside it
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      if (t > t1) return false;
      if (t > t0) t0 = t;
    } else {
      if (t < t0) return false;
      if (t < t1) t1 = t;
    }
  }
  end_clipped = t1 < 1.0;
  const double sx = x0, sy = y0;
  x0 = sx + t0 * dx;
  y0 = sy + t0 * dy;
  x1 = sx + t1 * dx;
  y1 = sy + t1 * dy;
  return true;
}

// clip_segment_any, with the common lidar ray (both ends inside) answered without its four
// divisions: the loop would keep t0 = 0 and t1 = 1 there, since rounding is monotonic (q >= 0
// where p < 0, q >= p where p > 0), and write these very values.
inline bool clip_segment(double& x0, double& y0, double& x1, double& y1, double xmin, double ymin,
                         double xmax, double ymax, bool& end_clipped) {
  if (x0 >= xmin && x0 <= xmax && y0 >= ymin && y0 <= ymax && x1 >= xmin && x1 <= xmax &&
      y1 >= ymin && y1 <= ymax) {
    end_clipped = false;
    const double sx = x0, sy = y0;
    x1 = sx + (x1 - sx);
    y1 = sy + (y1 - sy);
    return true;
  }
  return clip_segment_any(x0, y0, x1, y1, xmin, ymin, xmax, ymax, end_clipped);
}

// How many steps of s (+1 or -1) take a storage coordinate from p in [0, n) out of [0, n): the
// step on which it wraps.
inline int steps_to_wrap(int p, int s, int n) {
  return s > 0 ? n - p : p + 1;
}

// Longest walk (major-axis steps) the closed-form walk of trace_line_from() takes; longer ones
// step Bresenham's error. And the shift of its reciprocal.
constexpr int kClosedFormMaxSteps = 4096;
constexpr int kRecipShift = 38;

// trace_line (below) from the start cell's storage column and row (cx0 mod nx, cy0 mod ny), for
// callers that know them without the two divisions, along (dx, dy) = (cx1 - cx0, cy1 - cy0).
//
// The line crosses at most one storage column wrap and one row wrap (its cells lie in a window
// of nx x ny), and the step at which each happens is known in advance, so the walk runs in at
// most three pieces with a linear storage index (+major stride every step, the minor steps in
// closed form) and no wrap test per cell: the walk is the hot loop of lidar clearing.
//
// The first `skip` steps are not visited (a caller that knows those cells need nothing): the
// cell of step k lies k cells from the start along the major axis and at most k along the
// minor, so with every cell within Chebyshev distance R of the start known, skip = R + 1.
template <typename Visit>
void trace_line_from(int col, int row, int dx, int dy, int nx, int ny, bool include_end,
                     Visit&& visit, int skip = 0) {
  const int adx = std::abs(dx), ady = std::abs(dy);
  const int sx = dx >= 0 ? 1 : -1, sy = dy >= 0 ? 1 : -1;
  // Major axis a, minor axis b: step a every time, b when the error crosses half a cell.
  const bool x_major = adx >= ady;
  const int da = x_major ? adx : ady, db = x_major ? ady : adx;
  const int steps = include_end ? da + 1 : da;
  if (steps <= 0) return;
  const std::ptrdiff_t sxs = sx, sys = std::ptrdiff_t(sy) * nx;
  const std::ptrdiff_t stride_a = x_major ? sxs : sys, stride_b = x_major ? sys : sxs;
  // What to add to the index when a coordinate wraps: one row (or the whole grid) backwards.
  const std::ptrdiff_t unwrap_x = -sxs * nx, unwrap_y = -sys * ny;
  const int pa = x_major ? col : row, pb = x_major ? row : col;
  const int na = x_major ? nx : ny, nb = x_major ? ny : nx;
  // The visit at major step k has taken m(k) minor steps, the unique m with
  // err(k) = da/2 - k*db + m*da in [0, da). The minor coordinate wraps on its steps_to_wrap-th
  // (M-th) minor step, taken in the step to the first k with m(k) >= M, that is
  // k*db > da/2 + (M-1)*da. The line takes db minor steps in all, so there is no minor wrap
  // (and no division, the slow part of a short ray) unless M <= db.
  int wrap_a = steps_to_wrap(pa, x_major ? sx : sy, na);
  int wrap_b = steps;  // none within the walk
  if (const int m = steps_to_wrap(pb, x_major ? sy : sx, nb); m <= db) {
    const std::int64_t k = (std::int64_t(da / 2) + std::int64_t(m - 1) * da) / db + 1;
    if (k < steps) wrap_b = int(k);
  }
  const std::ptrdiff_t fix_a = x_major ? unwrap_x : unwrap_y, fix_b = x_major ? unwrap_y : unwrap_x;
  std::ptrdiff_t i = std::ptrdiff_t(row) * nx + col;
  // The walk in pieces between the wrap steps: walk(n) visits n cells and moves i on, and at a
  // wrap step (maybe both) the linear index, one row or column off the storage, is put back.
  const auto in_pieces = [&](auto&& walk) {
    for (int k = 0;;) {
      const int stop = std::min({steps, wrap_a, wrap_b});
      walk(stop - k);
      k = stop;
      if (k == steps) return;
      if (k == wrap_a) {
        i += fix_a;
        wrap_a = steps;
      }
      if (k == wrap_b) {
        i += fix_b;
        wrap_b = steps;
      }
    }
  };
  if (da >= 1 && da <= kClosedFormMaxSteps) {
    // The minor steps after k major steps in closed form, m(k) = (k db + c) / da with
    // c = da - 1 - da / 2 (the m that keeps Bresenham's error in [0, da)), the division a
    // multiply by a rounded-up reciprocal, exact for every numerator here (da <= 4096: numerators
    // below 2^25, their product with da below 2^38 = 2^kRecipShift). Each cell's index then
    // depends on the step count alone, not on the cell before: no chain of error updates and
    // no branch for the predictor to miss. Here i is the index without the minor steps.
    const std::uint64_t recip =
        ((std::uint64_t{1} << kRecipShift) + std::uint64_t(da) - 1) / std::uint64_t(da);
    std::uint64_t num = std::uint64_t(da - 1 - da / 2);
    in_pieces([&](int n) {
      if (skip > 0) {  // steps taken without a visit, in this piece and maybe the next
        const int k = std::min(n, skip);
        i += stride_a * k;
        num += std::uint64_t(db) * std::uint64_t(k);
        skip -= k;
        n -= k;
      }
      for (; n > 0; --n) {
        const auto m = std::ptrdiff_t((num * recip) >> kRecipShift);
        visit(std::size_t(i + m * stride_b));
        i += stride_a;
        num += std::uint64_t(db);
      }
    });
    return;
  }
  int err = da / 2;
  in_pieces([&](int n) {
    // A count down to zero: one instruction fewer per cell than comparing k with stop.
    for (; n > 0; --n) {
      if (skip > 0) {
        --skip;
      } else {
        visit(std::size_t(i));
      }
      i += stride_a;
      err -= db;
      if (err < 0) {
        err += da;
        i += stride_b;
      }
    }
  });
}

// Calls visit(storage_index) for the cells on the Bresenham line from global cell (cx0, cy0) to
// (cx1, cy1) of a grid of nx x ny cells, the start cell included, the end cell only when
// include_end. Both cells must lie inside the window (the caller clips); then every cell visited
// does too, and each is visited once.
template <typename Visit>
void trace_line(int cx0, int cy0, int cx1, int cy1, int nx, int ny, bool include_end,
                Visit&& visit) {
  trace_line_from(wrap(cx0, nx), wrap(cy0, ny), cx1 - cx0, cy1 - cy0, nx, ny, include_end,
                  static_cast<Visit&&>(visit));
}

}  // namespace carril::fw::grid
