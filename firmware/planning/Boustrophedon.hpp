#pragma once
// Boustrophedon coverage of a free-cell mask (Choset's cell decomposition on a grid): a sweep line
// along x splits each column into free intervals; an interval continues the cell of the one
// interval it overlaps in the previous column when that one overlaps it alone, and otherwise
// starts a new cell (a split, a merge, an obstacle's start or end). A cell also ends where its top
// or bottom jumps by more than max_boundary_step cells from one column to the next (a door in the
// wall the lanes run against): lanes joined at such a jump would leave the step unswept.
//
// Each cell is covered by vertical lanes (along the sweep line) on one grid of columns across the
// map, lane_spacing_m apart, plus a lane on its first or last column where that border faces a
// wall (an open border is swept from the cell beyond it, whose lanes are on the same grid); with
// lane_grid off, each cell's lanes are spread evenly from its first column to its last. A cell
// whose lanes are all shorter than the spacing is one pass through the middles of its columns
// instead (CoverCell::single_pass). Neighbouring
// lanes are joined at their ends by a U-turn: two quarter arcs of turn_radius_m and the straight
// between (a half circle when the radius is half the spacing), kept inside the cell's columns
// between the two lanes.
//
// A visit of a cell enters at one of its four corners (first or last lane, bottom or top); the
// tour orders the visits to keep the transitions short: greedy nearest from the start, then 2-opt
// (reversing a run of visits reverses each route) and corner flips, at most max_order_passes
// passes; the plain order (cells as numbered, each from its first lane's bottom) improved the
// same way is kept when it is cheaper. A transition costs the larger of the straight distance and
// the free-space distance between the two cells (8-connected, computed once per cell by
// decompose()), so cells in another room are as far as the door makes them.
//
// Buffers are sized by init(); decompose(), order() and route() never allocate.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct BoustrophedonConfig {
  double lane_spacing_m = 0.45;         // largest distance between neighbouring lanes [m]
  double turn_radius_m = 0.0;           // U-turn arcs; 0: half the lane spacing [m]
  double arc_step_rad = 0.3;            // arcs as polylines, a point every this angle [rad]
  int max_boundary_step = 2;            // a larger jump of a cell's top or bottom ends it [cells]
  std::uint32_t max_order_passes = 50;  // improvement passes of the tour [passes]
  // Lanes on one grid of columns across the map (multiples of the spacing), a cell's border
  // getting a lane of its own only where more than open_border_fraction of it faces blocked
  // cells; false: each cell's lanes spread evenly from its first column to its last.
  bool lane_grid = true;
  double open_border_fraction = 0.0;  // [-]

  Status validate() const;
};

// A cell of the decomposition: one free interval per column from x0 to x1.
struct CoverCell {
  int x0 = 0, x1 = 0;            // first and last column [cells]
  std::uint32_t first_lane = 0;  // index of its first lane
  std::uint32_t lanes = 0;       // lane count
  std::uint32_t area = 0;        // free cells [cells]
  // Every lane shorter than the lane spacing: the cell is a strip across the sweep line, driven
  // in one pass through its lanes' midpoints (U-turns tighter than the lanes are long would
  // overshoot them).
  bool single_pass = false;
};

// A lane: a vertical segment through the centres of a column's interval.
struct CoverLane {
  int column = 0;                 // [cells]
  int y0 = 0, y1 = 0;             // first and last row of the interval [cells]
  double x = 0.0;                 // world x [m]
  double y0_m = 0.0, y1_m = 0.0;  // world y of its bottom and top ends [m]
  // The U-turn toward the next lane of the cell stays below top_join_m and above bottom_join_m:
  // the lowest top and the highest bottom of the columns between the two lanes [m].
  double top_join_m = 0.0, bottom_join_m = 0.0;
  std::uint16_t cell = 0;
};

// One cell's visit: entry bit 0 = start at the top, bit 1 = start at the last lane.
struct CellVisit {
  std::uint16_t cell = 0;
  std::uint8_t entry = 0;
};

class Boustrophedon {
 public:
  static constexpr std::uint16_t kNoCell = 0xFFFF;
  static constexpr std::size_t kMaxCellsLimit = 4096;  // the gap table is cells^2

  // Buffers for masks up to max_nx x max_ny and the given counts (init time).
  Status init(int max_nx, int max_ny, std::size_t max_cells, std::size_t max_lanes);

  // Decomposes the free cells of mask (row-major nx * ny, index y * nx + x, non-zero = free) whose
  // cell (0, 0) has its lower-left corner at (origin_x, origin_y) [m], lays the lanes and measures
  // the gaps between cells. An error names what is wrong: no free cell, more cells or lanes than
  // the buffers hold, a mask larger than init()'s, a bad setting.
  Status decompose(const std::uint8_t* mask, int nx, int ny, double resolution_m, double origin_x,
                   double origin_y, const BoustrophedonConfig& cfg);

  std::size_t cell_count() const { return cells_n_; }
  const CoverCell& cell(std::size_t k) const { return cells_[k]; }
  std::size_t lane_count() const { return lanes_n_; }
  const CoverLane& lane(std::size_t k) const { return lanes_[k]; }
  // The cell a grid cell belongs to; kNoCell for a blocked cell or outside the mask.
  std::uint16_t label(int x, int y) const;
  // Free-space distance between two cells (0 when they touch); a large value when they are not
  // connected [m].
  double gap_m(std::size_t a, std::size_t b) const;

  // Where a visit starts and ends [m], and the same visit driven backwards.
  Vec2 entry_point(const CellVisit& v) const;
  Vec2 exit_point(const CellVisit& v) const;
  CellVisit reversed(const CellVisit& v) const;
  // Cost of moving from point p of cell a to point q of cell b [m]; a = kNoCell: p is the start.
  double transition_cost(std::uint16_t a, const Vec2& p, std::uint16_t b, const Vec2& q) const;
  // Transitions of the tour v[0..n) from `start` [m].
  double tour_cost(const Vec2& start, const CellVisit* v, std::size_t n) const;

  // Orders the visits of every cell from `start` [m]; returns the tour's cost [m].
  double order(const Vec2& start);
  const CellVisit* tour() const { return tour_.get(); }
  std::size_t tour_size() const { return cells_n_; }

  // The route of a visit: waypoints [m] along its lanes and U-turns. false when `out` is too
  // small (out then holds a prefix).
  template <std::size_t N>
  bool route(const CellVisit& v, StaticVector<Vec2, N>& out) const {
    out.clear();
    return route_impl(v, &out, &push_point<N>);
  }
  // The same, appended to what `out` holds.
  template <std::size_t N>
  bool append_route(const CellVisit& v, StaticVector<Vec2, N>& out) const {
    return route_impl(v, &out, &push_point<N>);
  }
  // Appends a U-turn laid as the lanes' own: from a lane at x = ax [m] driven up (or down) to
  // one at bx driven the other way, within rows top and bottom [m]: the points from where it
  // leaves the first lane to where it meets the second.
  template <std::size_t N>
  bool u_turn(double ax, double bx, bool up, double top, double bottom,
              StaticVector<Vec2, N>& out) const {
    return u_turn_impl(ax, bx, up, top, bottom, &out, &push_point<N>);
  }

 private:
  using PushFn = bool (*)(void* out, const Vec2& p);
  template <std::size_t N>
  static bool push_point(void* out, const Vec2& p) {
    return static_cast<StaticVector<Vec2, N>*>(out)->try_push_back(p);
  }
  bool route_impl(const CellVisit& v, void* out, PushFn push) const;
  bool u_turn_impl(double ax, double bx, bool up, double top, double bottom, void* out,
                   PushFn push) const;
  bool push_arc(void* out, PushFn push, const Vec2& c, double r, double a0, double a1, double vy,
                bool skip_first) const;
  Status lay_lanes(std::size_t k);
  void place_lane(std::size_t k, CoverLane& l, int column) const;  // on cell k's interval there
  double wall_fraction(std::size_t cell, int column, int beyond) const;
  void interval_of(std::size_t cell, int column, int& y0, int& y1) const;
  void measure_gaps();
  std::size_t index(int x, int y) const {
    return std::size_t(y) * std::size_t(nx_) + std::size_t(x);
  }
  const CoverLane& lane_of(const CellVisit& v, std::size_t m) const;
  double improve(CellVisit* t) const;  // 2-opt and corner flips; returns the tour's cost

  BoustrophedonConfig cfg_;
  int max_nx_ = 0, max_ny_ = 0;
  std::size_t max_cells_ = 0, max_lanes_ = 0;
  int nx_ = 0, ny_ = 0;
  double res_ = 0.05, ox_ = 0.0, oy_ = 0.0;
  Vec2 start_{0.0, 0.0};

  struct Interval {
    int y0, y1;
    std::uint16_t cell;
  };
  std::unique_ptr<std::uint16_t[]> label_;  // cell per grid cell
  std::unique_ptr<Interval[]> prev_, cur_;  // the intervals of two neighbouring columns
  std::unique_ptr<std::uint16_t[]> prev_hits_, cur_hits_, cur_link_;
  std::unique_ptr<CoverCell[]> cells_;
  std::unique_ptr<CoverLane[]> lanes_;
  std::unique_ptr<std::uint16_t[]> gap_;   // cells^2 gaps [grid cells], 0xFFFF: apart
  std::unique_ptr<std::uint16_t[]> dist_;  // breadth-first distances [grid cells]
  std::unique_ptr<std::int32_t[]> queue_;
  std::unique_ptr<CellVisit[]> tour_, scratch_;
  std::unique_ptr<std::uint8_t[]> used_;
  std::size_t cells_n_ = 0, lanes_n_ = 0;
};

}  // namespace carril::fw
