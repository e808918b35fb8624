#include "host_sim/sensors/ConvexFill.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <utility>

namespace carril::sim {
namespace {

using i64 = std::int64_t;

// OpenCV steps edges and outlines in 16.16 fixed point whatever the caller's shift.
constexpr int kXyShift = 16;
constexpr i64 kXyHalf = i64(1) << (kXyShift - 1);
constexpr int kUp = kXyShift - kFillShift;      // FixedPt -> 16.16
constexpr i64 kDelta = (1 << kFillShift) >> 1;  // rounds a FixedPt to the nearest pixel

struct Canvas {
  std::uint8_t* data;
  int w, h;
  std::size_t step;
  std::uint8_t bgr[3];
  std::uint8_t pat[48];  // sixteen pixels of the colour, for spans
};

// Two's complement wrap, as the hardware gives it: OpenCV steps edge x by repeated int64
// addition, which a jump over many rows must reproduce even where it would overflow.
inline i64 wrap_mul(i64 a, i64 b) {
  return i64(std::uint64_t(a) * std::uint64_t(b));
}
inline i64 wrap_add(i64 a, i64 b) {
  return i64(std::uint64_t(a) + std::uint64_t(b));
}

// OpenCV 4.6 moves a clipped end by (a - y1) * (x2 - x1) / (y2 - y1) in double (the int64
// product overflows for vertices some 1e5 px away), truncated towards zero.
inline i64 clip_step(i64 a, i64 b, i64 c) {
  return i64(double(a) * double(b) / double(c));
}

inline int outcode(i64 x, i64 y, i64 right, i64 bottom) {
  return (x < 0) + (x > right) * 2 + (y < 0) * 4 + (y > bottom) * 8;
}

// cv::clipLine on [0, right] x [0, bottom]: Cohen-Sutherland, rows first. The outline's steps start
// from the clipped points, so the clipping must be OpenCV's to the last bit, not merely a correct
// one.
bool clip_line(i64 right, i64 bottom, i64& x1, i64& y1, i64& x2, i64& y2) {
  int c1 = outcode(x1, y1, right, bottom), c2 = outcode(x2, y2, right, bottom);
  if ((c1 & c2) == 0 && (c1 | c2) != 0) {
    if (c1 & 12) {
      const i64 a = c1 < 8 ? 0 : bottom;
      x1 += clip_step(a - y1, x2 - x1, y2 - y1);
      y1 = a;
      c1 = (x1 < 0) + (x1 > right) * 2;
    }
    if (c2 & 12) {
      const i64 a = c2 < 8 ? 0 : bottom;
      x2 += clip_step(a - y2, x2 - x1, y2 - y1);
      y2 = a;
      c2 = (x2 < 0) + (x2 > right) * 2;
    }
    if ((c1 & c2) == 0 && (c1 | c2) != 0) {
      if (c1) {
        const i64 a = c1 == 1 ? 0 : right;
        y1 += clip_step(a - x1, y2 - y1, x2 - x1);
        x1 = a;
        c1 = 0;
      }
      if (c2) {
        const i64 a = c2 == 1 ? 0 : right;
        y2 += clip_step(a - x2, y2 - y1, x2 - x1);
        x2 = a;
        c2 = 0;
      }
    }
  }
  return (c1 | c2) == 0;
}

// A continuous width x height BGR image to fill in colour (b, g, r), its span pattern made.
Canvas canvas(std::uint8_t* bgr, int width, int height, std::uint8_t b, std::uint8_t g,
              std::uint8_t r) {
  Canvas c{bgr, width, height, std::size_t(width) * 3, {b, g, r}, {}};
  for (int k = 0; k < 48; k += 3) {
    c.pat[k] = b;
    c.pat[k + 1] = g;
    c.pat[k + 2] = r;
  }
  return c;
}

// The colour as two scalars the compiler can keep in registers across a loop of byte stores
// (stores through uint8_t* may alias the Canvas, so its bytes would be reloaded every pixel).
struct Colour3 {
  std::uint16_t bg;
  std::uint8_t r;
  explicit Colour3(const Canvas& c) : r(c.bgr[2]) { std::memcpy(&bg, c.bgr, 2); }
  void store(std::uint8_t* p) const {
    std::memcpy(p, &bg, 2);
    p[2] = r;
  }
};

inline void put(const Canvas& c, int x, int y) {
  if (unsigned(x) < unsigned(c.w) && unsigned(y) < unsigned(c.h)) {
    std::uint8_t* p = c.data + std::size_t(y) * c.step + std::size_t(x) * 3;
    p[0] = c.bgr[0];
    p[1] = c.bgr[1];
    p[2] = c.bgr[2];
  }
}

// One outline edge, as OpenCV's Line2: clipped to the image in 16.16, stepped one pixel along
// the major axis from the left (or top) end, plus the other end rounded on its own.
void outline_edge(const Canvas& c, i64 x1, i64 y1, i64 x2, i64 y2) {
  const i64 right = (i64(c.w) << kXyShift) - 1, bottom = (i64(c.h) << kXyShift) - 1;
  if (!clip_line(right, bottom, x1, y1, x2, y2)) return;
  i64 dx = x2 - x1, dy = y2 - y1;
  const i64 ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
  if (ax > ay) {
    if (dx < 0) {
      std::swap(x1, x2);
      std::swap(y1, y2);
      dy = -dy;
    }
    const i64 step = (dy << kXyShift) / (ax | 1);
    put(c, int((x2 + kXyHalf) >> kXyShift), int((y2 + kXyHalf) >> kXyShift));
    // Points i = 0..count-1 at column x0 + i; those left or right of the image set nothing, so
    // the loop runs over the others only, starting y as far along as OpenCV's steps take it.
    const i64 x0 = (x1 + kXyHalf) >> kXyShift, count = ((x2 - x1) >> kXyShift) + 1;
    const i64 i0 = std::max<i64>(0, -x0), i1 = std::min<i64>(count, c.w - x0);
    if (i0 >= i1) return;
    const Colour3 colour(c);
    i64 y = y1 + kXyHalf + i0 * step;
    std::uint8_t* p = c.data + (x0 + i0) * 3;
    for (i64 i = i0; i < i1; ++i, p += 3, y += step) {
      const int row = int(y >> kXyShift);
      if (unsigned(row) < unsigned(c.h)) colour.store(p + std::size_t(row) * c.step);
    }
  } else {
    if (dy < 0) {
      std::swap(x1, x2);
      std::swap(y1, y2);
      dx = -dx;
    }
    const i64 step = (dx << kXyShift) / (ay | 1);
    put(c, int((x2 + kXyHalf) >> kXyShift), int((y2 + kXyHalf) >> kXyShift));
    const i64 y0 = (y1 + kXyHalf) >> kXyShift, count = ((y2 - y1) >> kXyShift) + 1;
    const i64 i0 = std::max<i64>(0, -y0), i1 = std::min<i64>(count, c.h - y0);
    if (i0 >= i1) return;
    const Colour3 colour(c);
    i64 x = x1 + kXyHalf + i0 * step;
    std::uint8_t* p = c.data + std::size_t(y0 + i0) * c.step;
    for (i64 i = i0; i < i1; ++i, p += c.step, x += step) {
      const int col = int(x >> kXyShift);
      if (unsigned(col) < unsigned(c.w)) colour.store(p + std::size_t(col) * 3);
    }
  }
}

// Pixels xl..xr (inclusive, 0 <= xl <= xr < width) of `row`. A store of the pattern at any
// multiple of 3 bytes into the span keeps the colour's phase, so each span is two to a few
// unaligned block stores, the last overlapping the one before, rather than a loop of pixels.
inline void span(const Canvas& c, std::uint8_t* row, int xl, int xr) {
  std::uint8_t* p = row + std::size_t(xl) * 3;
  const std::size_t len = std::size_t(xr - xl + 1) * 3;
  std::uint8_t* const end = p + len;
  if (len >= 48) {
    for (; p + 48 <= end; p += 48) std::memcpy(p, c.pat, 48);
    std::memcpy(end - 48, c.pat, 48);
  } else if (len >= 24) {
    std::memcpy(p, c.pat, 24);
    std::memcpy(end - 24, c.pat, 24);
  } else if (len >= 12) {
    std::memcpy(p, c.pat, 12);
    std::memcpy(end - 12, c.pat, 12);
  } else if (len >= 6) {
    std::memcpy(p, c.pat, 6);
    std::memcpy(end - 6, c.pat, 6);
  } else {
    std::memcpy(p, c.pat, 3);
  }
}

}  // namespace

void fill_convex_poly(std::uint8_t* bgr, int width, int height, const FixedPt* v, int n,
                      std::uint8_t b, std::uint8_t g, std::uint8_t r) {
  if (n <= 0 || width <= 0 || height <= 0) return;
  i64 xmin = v[0].x, xmax = xmin, ymin = v[0].y, ymax = ymin;
  int imin = 0;
  for (int i = 1; i < n; ++i) {
    if (v[i].y < ymin) {
      ymin = v[i].y;
      imin = i;
    }
    ymax = std::max<i64>(ymax, v[i].y);
    xmin = std::min<i64>(xmin, v[i].x);
    xmax = std::max<i64>(xmax, v[i].x);
  }
  // Wholly left of, above, right of or below the image: every outline edge is clipped away
  // (both ends outside on one side) and the fill's rounded box misses the image.
  if (xmax < -kDelta || ymax < -kDelta || xmin >= i64(width) << kFillShift ||
      ymin >= i64(height) << kFillShift) {
    return;
  }
  const Canvas c = canvas(bgr, width, height, b, g, r);
  // The outline first, from the last vertex round to it, as OpenCV draws it.
  i64 px = i64(v[n - 1].x) << kUp, py = i64(v[n - 1].y) << kUp;
  for (int i = 0; i < n; ++i) {
    const i64 qx = i64(v[i].x) << kUp, qy = i64(v[i].y) << kUp;
    outline_edge(c, px, py, qx, qy);
    px = qx;
    py = qy;
  }
  const i64 rxmin = (xmin + kDelta) >> kFillShift, rxmax = (xmax + kDelta) >> kFillShift;
  const i64 rymin = (ymin + kDelta) >> kFillShift, rymax = (ymax + kDelta) >> kFillShift;
  if (n < 3 || rxmax < 0 || rymax < 0 || rxmin >= width || rymin >= height) return;
  const int ylast = int(std::min<i64>(rymax, height - 1));

  // The two chains from the top vertex: forwards (+1) and backwards (+n-1) round the polygon.
  // Like OpenCV, an edge starts at its upper vertex's x whatever row it is picked up on, its
  // slope is rounded to the nearest 16.16 step per row, and one count of edges left serves both
  // chains; when it runs out the fill stops, before drawing that row.
  struct Edge {
    int idx, di;
    i64 x, dx;
    int ye;
  } e[2] = {{imin, 1, -(i64(1) << kXyShift), 0, int(rymin)},
            {imin, n - 1, -(i64(1) << kXyShift), 0, int(rymin)}};
  int edges = n;
  int y = int(rymin);
  for (;;) {
    for (Edge& ed : e) {
      if (y < ed.ye) continue;
      int idx0 = ed.idx, idx = idx0 + ed.di;
      if (idx >= n) idx -= n;
      while (edges-- > 0) {
        const int ty = int((i64(v[idx].y) + kDelta) >> kFillShift);
        if (ty > y) {
          const i64 xs = i64(v[idx0].x) << kUp, xe = i64(v[idx].x) << kUp;
          ed.ye = ty;
          ed.dx = ((xe - xs) * 2 + (ty - y)) / (2 * (ty - y));
          ed.x = xs;
          ed.idx = idx;
          break;
        }
        idx0 = idx;
        idx += ed.di;
        if (idx >= n) idx -= n;
      }
    }
    if (edges < 0) break;
    if (y < 0) {
      // Rows above the image draw nothing; OpenCV steps through them one at a time, we jump to
      // the next row where an edge ends (or row 0), moving the edges as far.
      const int next = std::min({e[0].ye, e[1].ye, 0});
      e[0].x = wrap_add(e[0].x, wrap_mul(e[0].dx, next - y));
      e[1].x = wrap_add(e[1].x, wrap_mul(e[1].dx, next - y));
      y = next;
      continue;
    }
    // The rows up to where an edge ends (or the last row): no edge changes, only spans.
    const int stop = std::min({e[0].ye, e[1].ye, ylast + 1});
    i64 xa = e[0].x, xb = e[1].x;
    const i64 da = e[0].dx, db = e[1].dx;
    std::uint8_t* row = bgr + std::size_t(y) * c.step;
    // Both edges round into the image on the first and last row, so on every row between (x is
    // linear in the row): no clamping. The common case, inside the image.
    const i64 lo = -kXyHalf, hi = (i64(width) << kXyShift) - kXyHalf - 1;
    const i64 xa_end = xa + da * (stop - 1 - y), xb_end = xb + db * (stop - 1 - y);
    if (std::min({xa, xb, xa_end, xb_end}) >= lo && std::max({xa, xb, xa_end, xb_end}) <= hi) {
      for (; y < stop; ++y, row += c.step, xa += da, xb += db) {
        span(c, row, int((std::min(xa, xb) + kXyHalf) >> kXyShift),
             int((std::max(xa, xb) + kXyHalf) >> kXyShift));
      }
    }
    for (; y < stop; ++y, row += c.step, xa += da, xb += db) {
      const int x1 = int((std::min(xa, xb) + kXyHalf) >> kXyShift);
      const int x2 = int((std::max(xa, xb) + kXyHalf) >> kXyShift);
      if (x2 >= 0 && x1 < width) span(c, row, std::max(x1, 0), std::min(x2, width - 1));
    }
    e[0].x = xa;
    e[1].x = xb;
    if (y > ylast) break;
  }
}

void fill_rect(std::uint8_t* bgr, int width, int height, int x0, int y0, int x1, int y1,
               std::uint8_t b, std::uint8_t g, std::uint8_t r) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, width - 1);
  y1 = std::min(y1, height - 1);
  if (x0 > x1 || y0 > y1) return;
  const Canvas c = canvas(bgr, width, height, b, g, r);
  for (int y = y0; y <= y1; ++y) span(c, bgr + std::size_t(y) * c.step, x0, x1);
}

}  // namespace carril::sim
