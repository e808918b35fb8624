#include "firmware/planning/Boustrophedon.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace carril::fw {

namespace {
constexpr std::uint16_t kApart = 0xFFFF;  // gap between cells that are not connected
constexpr double kApartCost = 1.0e6;      // [m]
}  // namespace

Status BoustrophedonConfig::validate() const {
  return Checks("coverage.boustrophedon")
      .range("lane_spacing_m", lane_spacing_m, 0.02, 10.0, "m")
      .range("turn_radius_m", turn_radius_m, 0.0, 10.0, "m")
      .range("arc_step_rad", arc_step_rad, 0.02, 1.6, "rad")
      .range("max_boundary_step", max_boundary_step, 0.0, 10000.0, "cells")
      .range("max_order_passes", max_order_passes, 0.0, 10000.0, "passes")
      .range("open_border_fraction", open_border_fraction, 0.0, 1.0, "")
      .result();
}

Status Boustrophedon::init(int max_nx, int max_ny, std::size_t max_cells, std::size_t max_lanes) {
  if (max_nx <= 0 || max_ny <= 0 || max_nx > 20000 || max_ny > 20000) {
    return Status::error("boustrophedon: grid %d x %d, expected 1 to 20000 cells a side", max_nx,
                         max_ny);
  }
  if (max_cells == 0 || max_cells > kMaxCellsLimit) {
    return Status::error("coverage.max_cells: %zu, expected 1 to %zu", max_cells, kMaxCellsLimit);
  }
  if (max_lanes == 0) return Status::error("coverage.max_lanes: 0, expected at least 1");
  max_nx_ = max_nx;
  max_ny_ = max_ny;
  max_cells_ = max_cells;
  max_lanes_ = max_lanes;
  const std::size_t n = std::size_t(max_nx) * std::size_t(max_ny);
  const std::size_t intervals = std::size_t(max_ny) / 2 + 1;
  label_ = std::make_unique<std::uint16_t[]>(n);
  prev_ = std::make_unique<Interval[]>(intervals);
  cur_ = std::make_unique<Interval[]>(intervals);
  prev_hits_ = std::make_unique<std::uint16_t[]>(intervals);
  cur_hits_ = std::make_unique<std::uint16_t[]>(intervals);
  cur_link_ = std::make_unique<std::uint16_t[]>(intervals);
  cells_ = std::make_unique<CoverCell[]>(max_cells);
  lanes_ = std::make_unique<CoverLane[]>(max_lanes);
  gap_ = std::make_unique<std::uint16_t[]>(max_cells * max_cells);
  dist_ = std::make_unique<std::uint16_t[]>(n);
  queue_ = std::make_unique<std::int32_t[]>(n);
  tour_ = std::make_unique<CellVisit[]>(max_cells);
  scratch_ = std::make_unique<CellVisit[]>(max_cells);
  used_ = std::make_unique<std::uint8_t[]>(max_cells);
  return Status::ok();
}

std::uint16_t Boustrophedon::label(int x, int y) const {
  if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return kNoCell;
  return label_[index(x, y)];
}

Status Boustrophedon::decompose(const std::uint8_t* mask, int nx, int ny, double resolution_m,
                                double origin_x, double origin_y, const BoustrophedonConfig& cfg) {
  cells_n_ = lanes_n_ = 0;
  nx_ = ny_ = 0;
  if (Status s = cfg.validate(); !s) return s;
  if (!label_) return Status::error("boustrophedon: not initialised");
  if (mask == nullptr || nx <= 0 || ny <= 0 || nx > max_nx_ || ny > max_ny_) {
    return Status::error("boustrophedon: grid %d x %d, the buffers hold %d x %d", nx, ny, max_nx_,
                         max_ny_);
  }
  if (!(resolution_m > 0.0) || !std::isfinite(origin_x) || !std::isfinite(origin_y)) {
    return Status::error("boustrophedon: resolution %g m, origin (%g, %g) m", resolution_m,
                         origin_x, origin_y);
  }
  cfg_ = cfg;
  nx_ = nx;
  ny_ = ny;
  res_ = resolution_m;
  ox_ = origin_x;
  oy_ = origin_y;
  std::size_t np = 0;
  for (int x = 0; x < nx; ++x) {
    // The free intervals of column x, bottom to top.
    std::size_t nc = 0;
    for (int y = 0; y < ny;) {
      if (mask[index(x, y)] == 0) {
        label_[index(x, y)] = kNoCell;
        ++y;
        continue;
      }
      const int y0 = y;
      while (y < ny && mask[index(x, y)] != 0) ++y;
      cur_[nc++] = {y0, y - 1, kNoCell};
    }
    // Which intervals of the two columns overlap (both lists sorted and disjoint).
    for (std::size_t i = 0; i < nc; ++i) cur_hits_[i] = 0;
    for (std::size_t p = 0; p < np; ++p) prev_hits_[p] = 0;
    for (std::size_t i = 0, p = 0; i < nc && p < np;) {
      if (cur_[i].y0 <= prev_[p].y1 && prev_[p].y0 <= cur_[i].y1) {
        ++cur_hits_[i];
        ++prev_hits_[p];
        cur_link_[i] = std::uint16_t(p);
      }
      if (cur_[i].y1 < prev_[p].y1) {
        ++i;
      } else if (cur_[i].y1 > prev_[p].y1) {
        ++p;
      } else {
        ++i;
        ++p;
      }
    }
    for (std::size_t i = 0; i < nc; ++i) {
      Interval& in = cur_[i];
      bool continues = cur_hits_[i] == 1 && prev_hits_[cur_link_[i]] == 1;
      if (continues) {
        const Interval& p = prev_[cur_link_[i]];
        continues = std::abs(in.y0 - p.y0) <= cfg.max_boundary_step &&
                    std::abs(in.y1 - p.y1) <= cfg.max_boundary_step;
      }
      if (continues) {
        in.cell = prev_[cur_link_[i]].cell;
        cells_[in.cell].x1 = x;
      } else {
        if (cells_n_ >= max_cells_) {
          cells_n_ = 0;
          return Status::error(
              "coverage: the area splits into more than %zu cells (raise "
              "coverage.max_cells)",
              max_cells_);
        }
        in.cell = std::uint16_t(cells_n_);
        cells_[cells_n_++] = CoverCell{x, x, 0, 0, 0, false};
      }
      cells_[in.cell].area += std::uint32_t(in.y1 - in.y0 + 1);
      for (int y = in.y0; y <= in.y1; ++y) label_[index(x, y)] = in.cell;
    }
    std::swap(prev_, cur_);
    np = nc;
  }
  if (cells_n_ == 0) return Status::error("coverage: the area has no free cell to cover");
  for (std::size_t k = 0; k < cells_n_; ++k) {
    if (Status s = lay_lanes(k); !s) {
      cells_n_ = 0;
      return s;
    }
  }
  measure_gaps();
  for (std::size_t k = 0; k < cells_n_; ++k) tour_[k] = CellVisit{std::uint16_t(k), 0};
  return Status::ok();
}

void Boustrophedon::interval_of(std::size_t cell, int column, int& y0, int& y1) const {
  y0 = ny_;
  y1 = -1;
  for (int y = 0; y < ny_; ++y) {
    if (label_[index(column, y)] != cell) continue;
    y0 = std::min(y0, y);
    y1 = y;
  }
}

// The fraction of the rows of `cell`'s interval in `column` whose cell in column `beyond` is
// blocked (or off the grid): how much of that border is a wall rather than another cell.
double Boustrophedon::wall_fraction(std::size_t cell, int column, int beyond) const {
  int y0 = 0, y1 = 0;
  interval_of(cell, column, y0, y1);
  if (y1 < y0) return 1.0;
  int blocked = 0;
  for (int y = y0; y <= y1; ++y) {
    if (beyond < 0 || beyond >= nx_ || label_[index(beyond, y)] == kNoCell) ++blocked;
  }
  return double(blocked) / double(y1 - y0 + 1);
}

void Boustrophedon::place_lane(std::size_t k, CoverLane& l, int column) const {
  l.column = column;
  interval_of(k, column, l.y0, l.y1);
  l.x = ox_ + (column + 0.5) * res_;
  l.y0_m = oy_ + (l.y0 + 0.5) * res_;
  l.y1_m = oy_ + (l.y1 + 0.5) * res_;
  l.cell = std::uint16_t(k);
}

Status Boustrophedon::lay_lanes(std::size_t k) {
  CoverCell& c = cells_[k];
  const int span = c.x1 - c.x0;                       // [columns]
  const double spacing = cfg_.lane_spacing_m / res_;  // [columns]
  std::size_t n = 0;
  const auto add = [&](int column) {
    if (lanes_n_ + n >= max_lanes_) return false;
    lanes_[lanes_n_ + n++].column = column;
    return true;
  };
  bool fits = true;
  if (span * res_ < 0.5 * cfg_.lane_spacing_m) {
    fits = add((c.x0 + c.x1) / 2);
  } else if (!cfg_.lane_grid) {
    // Evenly spread, the outer ones on the first and last columns.
    const std::size_t m =
        std::min(std::size_t(std::ceil(span / spacing - 1e-9)) + 1, std::size_t(span) + 1);
    for (std::size_t i = 0; i < m && fits; ++i) {
      fits = add(c.x0 + int(std::lround(double(i) * span / double(m - 1))));
    }
  } else {
    // On the map's one grid of columns (multiples of the spacing), so neighbouring cells keep
    // the spacing across an open border instead of each laying a lane on its own side of it;
    // a border that faces a wall gets its own lane (the tool must reach the wall). A grid lane
    // closer than half the spacing to a wall's lane moves halfway to the lane after it: the
    // U-turn between two lanes is as tight as they are close.
    const int half = int(std::ceil(0.5 * spacing));
    const bool wall0 = wall_fraction(k, c.x0, c.x0 - 1) > cfg_.open_border_fraction;
    const bool wall1 = wall_fraction(k, c.x1, c.x1 + 1) > cfg_.open_border_fraction;
    const auto grid = [&](long g) { return int(std::lround(double(g) * spacing)); };
    int last = -1;
    if (wall0) {
      fits = add(c.x0);
      last = c.x0;
    }
    for (long g = long(std::ceil(c.x0 / spacing - 1e-9)); fits; ++g) {
      int col = grid(g);
      if (col > c.x1) break;
      if (col <= last) continue;
      if (last >= 0 && col - last < half) {
        const int next = std::min(grid(g + 1), c.x1);
        if (next - last < 2 * half) continue;  // the next one is near enough
        col = (last + next) / 2;
      }
      fits = add(col);
      last = col;
    }
    if (fits && wall1 && last != c.x1) {
      if (n >= 1 && c.x1 - last < half) {
        const int before = n >= 2 ? lanes_[lanes_n_ + n - 2].column : c.x0;
        if (c.x1 - before < 2 * half) {
          --n;  // the one before is near enough
        } else {
          lanes_[lanes_n_ + n - 1].column = (before + c.x1) / 2;
        }
      }
      fits = add(c.x1);
    }
    if (fits && n == 0) fits = add((c.x0 + c.x1) / 2);  // open on both sides, narrower than a lane
  }
  if (!fits) {
    return Status::error("coverage: the area needs more than %zu lanes (raise coverage.max_lanes)",
                         max_lanes_);
  }
  c.first_lane = std::uint32_t(lanes_n_);
  c.lanes = std::uint32_t(n);
  for (std::size_t m = 0; m < n; ++m)
    place_lane(k, lanes_[lanes_n_ + m], lanes_[lanes_n_ + m].column);
  c.single_pass = n > 1;
  for (std::size_t m = 0; m < n; ++m) {
    const CoverLane& l = lanes_[lanes_n_ + m];
    if (l.y1_m - l.y0_m >= cfg_.lane_spacing_m) c.single_pass = false;
  }
  if (c.single_pass) {
    // One pass from the first column to the last: the visit's ends are those columns.
    n = 2;
    c.lanes = 2;
    place_lane(k, lanes_[lanes_n_], c.x0);
    place_lane(k, lanes_[lanes_n_ + 1], c.x1);
  }
  for (std::size_t m = 0; m < n; ++m) {
    CoverLane& l = lanes_[lanes_n_ + m];
    int top = l.y1, bottom = l.y0;
    if (m + 1 < n) {
      for (int col = l.column + 1; col <= lanes_[lanes_n_ + m + 1].column; ++col) {
        int y0 = 0, y1 = 0;
        interval_of(k, col, y0, y1);
        top = std::min(top, y1);
        bottom = std::max(bottom, y0);
      }
    }
    l.top_join_m = oy_ + (top + 0.5) * res_;
    l.bottom_join_m = oy_ + (bottom + 0.5) * res_;
  }
  lanes_n_ += n;
  return Status::ok();
}

// One breadth-first search (8-connected, over the free cells) from every cell: the first time
// it reaches a cell of another, that is their gap.
void Boustrophedon::measure_gaps() {
  const std::size_t n = std::size_t(nx_) * std::size_t(ny_);
  const std::size_t cells = cells_n_;
  for (std::size_t a = 0; a < cells; ++a) {
    std::uint16_t* row = &gap_[a * cells];
    for (std::size_t b = 0; b < cells; ++b) row[b] = kApart;
    row[a] = 0;
    std::size_t head = 0, tail = 0, found = 1;
    for (std::size_t k = 0; k < n; ++k) {
      dist_[k] = kApart;
      if (label_[k] == a) {
        dist_[k] = 0;
        queue_[tail++] = std::int32_t(k);
      }
    }
    while (head < tail && found < cells) {
      const std::size_t v = std::size_t(queue_[head++]);
      const int x = int(v % std::size_t(nx_)), y = int(v / std::size_t(nx_));
      const std::uint16_t d = std::uint16_t(std::min<int>(dist_[v] + 1, kApart - 1));
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int ux = x + dx, uy = y + dy;
          if (ux < 0 || uy < 0 || ux >= nx_ || uy >= ny_) continue;
          const std::size_t u = index(ux, uy);
          const std::uint16_t b = label_[u];
          if (b == kNoCell || dist_[u] != kApart) continue;
          dist_[u] = d;
          queue_[tail++] = std::int32_t(u);
          if (row[b] == kApart) {
            row[b] = d;
            ++found;
          }
        }
      }
    }
  }
}

double Boustrophedon::gap_m(std::size_t a, std::size_t b) const {
  const std::uint16_t g = gap_[a * cells_n_ + b];
  if (g == kApart) return kApartCost;
  return g <= 1 ? 0.0 : (g - 1) * res_;
}

const CoverLane& Boustrophedon::lane_of(const CellVisit& v, std::size_t m) const {
  const CoverCell& c = cells_[v.cell];
  return lanes_[c.first_lane + ((v.entry & 2) != 0 ? c.lanes - 1 - m : m)];
}

Vec2 Boustrophedon::entry_point(const CellVisit& v) const {
  const CoverLane& l = lane_of(v, 0);
  if (cells_[v.cell].single_pass) return {l.x, 0.5 * (l.y0_m + l.y1_m)};
  return {l.x, (v.entry & 1) != 0 ? l.y1_m : l.y0_m};
}

Vec2 Boustrophedon::exit_point(const CellVisit& v) const {
  const std::size_t n = cells_[v.cell].lanes;
  if (cells_[v.cell].single_pass) {
    const CoverLane& l = lane_of(v, n - 1);
    return {l.x, 0.5 * (l.y0_m + l.y1_m)};
  }
  const bool up_first = (v.entry & 1) == 0;
  const bool up_last = (n % 2 == 1) ? up_first : !up_first;
  const CoverLane& l = lane_of(v, n - 1);
  return {l.x, up_last ? l.y1_m : l.y0_m};
}

CellVisit Boustrophedon::reversed(const CellVisit& v) const {
  const std::size_t n = cells_[v.cell].lanes;
  const bool up_first = (v.entry & 1) == 0;
  const bool ends_top = (n % 2 == 1) ? up_first : !up_first;
  std::uint8_t last = v.entry & 2;
  if (n > 1) last = last != 0 ? 0 : 2;
  return CellVisit{v.cell, std::uint8_t(last | (ends_top ? 1 : 0))};
}

double Boustrophedon::transition_cost(std::uint16_t a, const Vec2& p, std::uint16_t b,
                                      const Vec2& q) const {
  const double straight = (q - p).norm();
  if (a == kNoCell) return straight;
  return std::max(straight, gap_m(a, b));
}

double Boustrophedon::tour_cost(const Vec2& start, const CellVisit* v, std::size_t n) const {
  double cost = 0.0;
  std::uint16_t cell = kNoCell;
  Vec2 at = start;
  for (std::size_t k = 0; k < n; ++k) {
    cost += transition_cost(cell, at, v[k].cell, entry_point(v[k]));
    cell = v[k].cell;
    at = exit_point(v[k]);
  }
  return cost;
}

double Boustrophedon::order(const Vec2& start) {
  start_ = start;
  const std::size_t n = cells_n_;
  if (n == 0) return 0.0;
  for (std::size_t k = 0; k < n; ++k) scratch_[k] = CellVisit{std::uint16_t(k), 0};
  const double plain = improve(scratch_.get());
  // Greedy: the nearest corner of any cell not yet visited.
  for (std::size_t k = 0; k < n; ++k) used_[k] = 0;
  std::uint16_t cell = kNoCell;
  Vec2 at = start;
  for (std::size_t step = 0; step < n; ++step) {
    double best = 0.0;
    CellVisit pick;
    bool any = false;
    for (std::size_t b = 0; b < n; ++b) {
      if (used_[b] != 0) continue;
      const std::uint8_t entries = cells_[b].lanes > 1 ? 4 : 2;
      for (std::uint8_t e = 0; e < entries; ++e) {
        const CellVisit v{std::uint16_t(b), e};
        const double c = transition_cost(cell, at, v.cell, entry_point(v));
        if (!any || c < best) {
          best = c;
          pick = v;
          any = true;
        }
      }
    }
    tour_[step] = pick;
    used_[pick.cell] = 1;
    cell = pick.cell;
    at = exit_point(pick);
  }
  const double greedy = improve(tour_.get());
  if (plain < greedy) {
    for (std::size_t k = 0; k < n; ++k) tour_[k] = scratch_[k];
    return plain;
  }
  return greedy;
}

double Boustrophedon::improve(CellVisit* t) const {
  const std::size_t n = cells_n_;
  const auto prev_cell = [&](std::size_t i) { return i == 0 ? kNoCell : t[i - 1].cell; };
  const auto prev_point = [&](std::size_t i) { return i == 0 ? start_ : exit_point(t[i - 1]); };
  // Cost of the transitions into and out of position i when it holds visit v.
  const auto around = [&](std::size_t i, const CellVisit& v) {
    double c = transition_cost(prev_cell(i), prev_point(i), v.cell, entry_point(v));
    if (i + 1 < n)
      c += transition_cost(v.cell, exit_point(v), t[i + 1].cell, entry_point(t[i + 1]));
    return c;
  };
  for (std::uint32_t pass = 0; pass < cfg_.max_order_passes; ++pass) {
    bool better = false;
    // Corner flips: the same first lane, entered from its other end.
    for (std::size_t i = 0; i < n; ++i) {
      CellVisit flip = t[i];
      flip.entry ^= 1;
      if (around(i, flip) < around(i, t[i]) - 1e-9) {
        t[i] = flip;
        better = true;
      }
    }
    // 2-opt: reverse the run t[i..j] (every visit in it driven backwards).
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i; j < n; ++j) {
        const std::uint16_t pc = prev_cell(i);
        const Vec2 pp = prev_point(i);
        double before = transition_cost(pc, pp, t[i].cell, entry_point(t[i]));
        double after = transition_cost(pc, pp, t[j].cell, exit_point(t[j]));
        if (j + 1 < n) {
          const Vec2 next = entry_point(t[j + 1]);
          before += transition_cost(t[j].cell, exit_point(t[j]), t[j + 1].cell, next);
          after += transition_cost(t[i].cell, entry_point(t[i]), t[j + 1].cell, next);
        }
        if (after < before - 1e-9) {
          for (std::size_t a = i, b = j; a < b; ++a, --b) std::swap(t[a], t[b]);
          for (std::size_t k = i; k <= j; ++k) t[k] = reversed(t[k]);
          better = true;
        }
      }
    }
    if (!better) break;
  }
  return tour_cost(start_, t, n);
}

// Points c + r (cos a, vy sin a) for a from a0 to a1, arc_step_rad apart.
bool Boustrophedon::push_arc(void* out, PushFn push, const Vec2& c, double r, double a0, double a1,
                             double vy, bool skip_first) const {
  const int steps = std::max(1, int(std::ceil(std::fabs(a1 - a0) / cfg_.arc_step_rad)));
  for (int s = skip_first ? 1 : 0; s <= steps; ++s) {
    const double a = a0 + (a1 - a0) * s / steps;
    if (!push(out, Vec2(c.x() + r * std::cos(a), c.y() + vy * r * std::sin(a)))) return false;
  }
  return true;
}

bool Boustrophedon::route_impl(const CellVisit& v, void* out, PushFn push) const {
  if (v.cell >= cells_n_) return true;
  const std::size_t n = cells_[v.cell].lanes;
  bool up = (v.entry & 1) == 0;
  if (!push(out, entry_point(v))) return false;
  if (cells_[v.cell].single_pass) {
    // Through the middle of every column (the strip may bend), from the first lane to the last.
    const CoverCell& c = cells_[v.cell];
    const bool forward = lane_of(v, 0).column == c.x0;
    for (int k = 1; k <= c.x1 - c.x0; ++k) {
      const int col = forward ? c.x0 + k : c.x1 - k;
      int y0 = 0, y1 = 0;
      interval_of(v.cell, col, y0, y1);
      if (!push(out, Vec2(ox_ + (col + 0.5) * res_, oy_ + (0.5 * (y0 + y1) + 0.5) * res_))) {
        return false;
      }
    }
    return true;
  }
  for (std::size_t m = 0; m < n; ++m) {
    const CoverLane& a = lane_of(v, m);
    if (m + 1 == n) return push(out, Vec2(a.x, up ? a.y1_m : a.y0_m));
    const CoverLane& b = lane_of(v, m + 1);
    const CoverLane& left = a.column < b.column ? a : b;  // holds the join's bounds
    if (!u_turn_impl(a.x, b.x, up, left.top_join_m, left.bottom_join_m, out, push)) return false;
    up = !up;
  }
  return true;
}

bool Boustrophedon::u_turn_impl(double ax, double bx, bool up, double top, double bottom, void* out,
                                PushFn push) const {
  const double radius = cfg_.turn_radius_m > 0.0 ? cfg_.turn_radius_m : 0.5 * cfg_.lane_spacing_m;
  const double dx = bx - ax, sgn = dx > 0.0 ? 1.0 : -1.0;
  const double r = std::min({radius, 0.5 * std::fabs(dx), 0.5 * (top - bottom)});
  const double vy = up ? 1.0 : -1.0;
  if (r < 0.25 * res_) {  // no room to turn: straight across at the end
    const double y = up ? top : bottom;
    return push(out, Vec2(ax, y)) && push(out, Vec2(bx, y));
  }
  const double yc = up ? top - r : bottom + r;
  const bool straight = std::fabs(dx) - 2.0 * r > 0.25 * res_;
  return push_arc(out, push, Vec2(ax + sgn * r, yc), r, sgn > 0 ? kPi : 0.0, 0.5 * kPi, vy,
                  false) &&
         push_arc(out, push, Vec2(bx - sgn * r, yc), r, 0.5 * kPi, sgn > 0 ? 0.0 : kPi, vy,
                  !straight);
}

}  // namespace carril::fw
