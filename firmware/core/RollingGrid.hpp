#pragma once
// A robot-centred window of cells over an unbounded world grid, stored as a 2D circular buffer:
// the world cell (cx, cy) lives at storage (cx mod nx, cy mod ny). Moving the window re-labels
// storage and resets only the rows and columns that enter it; nothing is copied or allocated.
// Storage is allocated once, by init(), before the first tick.
//
// Cells are addressed by their global index cx = floor(x / resolution) (world frame). The window
// covers [origin_cx, origin_cx + nx) x [origin_cy, origin_cy + ny).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Check.hpp"

namespace carril::fw {

template <typename T>
class RollingGrid {
 public:
  // Allocates nx * ny cells set to `fill` (init time only). false on a non-positive size or
  // resolution [cells, cells, m].
  bool init(int nx, int ny, double resolution_m, T fill) {
    if (nx <= 0 || ny <= 0 || !(resolution_m > 0.0)) return false;
    nx_ = nx;
    ny_ = ny;
    res_ = resolution_m;
    fill_ = fill;
    cells_ = std::make_unique<T[]>(std::size_t(nx) * std::size_t(ny));
    origin_cx_ = origin_cy_ = 0;
    clear();
    return true;
  }
  bool ready() const { return cells_ != nullptr; }

  int nx() const { return nx_; }                // window width [cells]
  int ny() const { return ny_; }                // window height [cells]
  double resolution() const { return res_; }    // cell side [m]
  int origin_cx() const { return origin_cx_; }  // global index of the window's first column
  int origin_cy() const { return origin_cy_; }  // global index of the window's first row
  double origin_x() const { return origin_cx_ * res_; }  // window's lower-left corner x [m]
  double origin_y() const { return origin_cy_ * res_; }  // window's lower-left corner y [m]
  T fill_value() const { return fill_; }

  // Global cell index of a world coordinate [m].
  int cell_of(double w) const { return static_cast<int>(std::floor(w / res_)); }
  // World coordinate of a cell's centre [m].
  double center_of(int c) const { return (c + 0.5) * res_; }

  bool contains(int cx, int cy) const {
    return cx >= origin_cx_ && cx < origin_cx_ + nx_ && cy >= origin_cy_ && cy < origin_cy_ + ny_;
  }
  // Global index of the world point (x, y) [m]; false when outside the window.
  bool world_to_cell(double x, double y, int& cx, int& cy) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    cx = cell_of(x);
    cy = cell_of(y);
    return contains(cx, cy);
  }

  // Cell by global index (checked inside the window; outside, the index wraps to a cell of the
  // storage all the same, so a failed check never touches memory outside it).
  T& at(int cx, int cy) {
    CARRIL_CHECK(contains(cx, cy));
    return cells_[index(cx, cy)];
  }
  const T& at(int cx, int cy) const {
    CARRIL_CHECK(contains(cx, cy));
    return cells_[index(cx, cy)];
  }
  // Cell by window index: lx in [0, nx), ly in [0, ny) from the window's lower-left corner.
  T& local(int lx, int ly) { return at(origin_cx_ + lx, origin_cy_ + ly); }
  const T& local(int lx, int ly) const { return at(origin_cx_ + lx, origin_cy_ + ly); }

  // Row access for fast sweeps: window row ly is storage row storage_row(ly); window column lx
  // is storage column (column_offset() + lx) mod nx. Two contiguous spans cover a row.
  T* storage_row(int ly) { return &cells_[std::size_t(wrap(origin_cy_ + ly, ny_)) * nx_]; }
  const T* storage_row(int ly) const {
    return &cells_[std::size_t(wrap(origin_cy_ + ly, ny_)) * nx_];
  }
  int column_offset() const { return wrap(origin_cx_, nx_); }
  // Storage row of window row 0 (window row ly is storage row (row_offset() + ly) mod ny).
  int row_offset() const { return wrap(origin_cy_, ny_); }

  void clear() {
    for (std::size_t i = 0, n = std::size_t(nx_) * ny_; i < n; ++i) cells_[i] = fill_;
  }

  // Moves the window so that its first cell is (cx, cy); cells that enter are reset to the fill
  // value, cells that stay keep their value. O(cells entering), never a copy.
  void move_origin(int cx, int cy) {
    const int dx = cx - origin_cx_, dy = cy - origin_cy_;
    if (dx == 0 && dy == 0) return;
    if (std::abs(dx) >= nx_ || std::abs(dy) >= ny_) {
      origin_cx_ = cx;
      origin_cy_ = cy;
      clear();
      return;
    }
    // Columns entering: [old_end, new_end) when moving +x, [new_start, old_start) when -x.
    const int col_lo = dx > 0 ? origin_cx_ + nx_ : cx;
    const int col_hi = dx > 0 ? cx + nx_ : origin_cx_;
    const int row_lo = dy > 0 ? origin_cy_ + ny_ : cy;
    const int row_hi = dy > 0 ? cy + ny_ : origin_cy_;
    origin_cx_ = cx;
    origin_cy_ = cy;
    for (int gx = col_lo; gx < col_hi; ++gx)
      for (int ly = 0; ly < ny_; ++ly) cells_[index(gx, origin_cy_ + ly)] = fill_;
    for (int gy = row_lo; gy < row_hi; ++gy) {
      T* row = &cells_[std::size_t(wrap(gy, ny_)) * nx_];
      for (int i = 0; i < nx_; ++i) row[i] = fill_;
    }
  }
  // Moves the window so that the world point (x, y) [m] is in its centre cell.
  void recenter(double x, double y) { move_origin(cell_of(x) - nx_ / 2, cell_of(y) - ny_ / 2); }

  // Copies the window out, row-major from its lower-left cell: out[ly * nx + lx] (for plots,
  // saved maps and planners that want a contiguous grid). out holds nx * ny values.
  void copy_to(T* out) const {
    const int off = column_offset();
    for (int ly = 0; ly < ny_; ++ly) {
      const T* row = storage_row(ly);
      T* o = out + std::size_t(ly) * nx_;
      for (int lx = 0; lx < nx_; ++lx) o[lx] = row[(off + lx) % nx_];
    }
  }

 private:
  static int wrap(int v, int n) {
    const int m = v % n;
    return m < 0 ? m + n : m;
  }
  std::size_t index(int cx, int cy) const {
    return std::size_t(wrap(cy, ny_)) * nx_ + std::size_t(wrap(cx, nx_));
  }

  int nx_ = 0, ny_ = 0;
  double res_ = 0.0;
  T fill_{};
  int origin_cx_ = 0, origin_cy_ = 0;
  std::unique_ptr<T[]> cells_;
};

}  // namespace carril::fw
