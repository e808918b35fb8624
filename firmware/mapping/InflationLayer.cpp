#include "firmware/mapping/InflationLayer.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/GridRay.hpp"

namespace carril::fw {

namespace {
// d2[i] = min(d2[i], min(left[i], right[i]) + dd): the hot loop of pass 2. The restrict
// qualifiers (the rows never overlap d2) let the compiler vectorise it without alias checks.
void min_plus_pair(std::int16_t* __restrict d2, const std::int16_t* __restrict left,
                   const std::int16_t* __restrict right, std::int16_t dd, int n) {
  for (int i = 0; i < n; ++i) {
    const auto v = std::int16_t(std::min(left[i], right[i]) + dd);
    d2[i] = std::min(d2[i], v);
  }
}
}  // namespace

Status InflationConfig::validate() const {
  return Checks("costmap.inflation")
      .range("inscribed_radius_m", inscribed_radius_m, 0.0, 10.0, "m")
      .range("inflation_radius_m", inflation_radius_m, 0.0, 10.0, "m")
      .fail_if(inflation_radius_m < inscribed_radius_m, "inflation_radius_m",
               "must be at least inscribed_radius_m")
      .range("cost_scaling_factor", cost_scaling_factor, 0.0, 1000.0, "1/m")
      .result();
}

bool InflationLayer::init(const InflationConfig& cfg, int nx, int ny, double resolution_m) {
  if (nx <= 0 || ny <= 0 || !(resolution_m > 0.0)) return false;
  // A hair of slack so that 0.55 / 0.05 is 11 cells, not 10.99999.
  constexpr double kSlack = 1e-9;
  const double r_cells = cfg.inflation_radius_m / resolution_m;
  if (!(r_cells <= kMaxRadiusCells)) return false;
  cfg_ = cfg;
  nx_ = nx;
  ny_ = ny;
  radius_ = int(std::floor(r_cells + kSlack));
  max_d2_ = int(std::floor(r_cells * r_cells + kSlack));
  const int cap = radius_ + 1;
  // Every D the passes can produce indexes the table: up to cap^2 + R^2, no bounds check needed.
  const int table_size = cap * cap + radius_ * radius_ + 1;
  table_ = std::make_unique<std::uint8_t[]>(std::size_t(table_size));
  const double ins_cells = cfg.inscribed_radius_m / resolution_m;
  for (int d2 = 0; d2 < table_size; ++d2) {
    std::uint8_t c = 0;
    if (d2 == 0) {
      c = cost::kLethal;
    } else if (d2 <= max_d2_) {
      const double d_cells = std::sqrt(double(d2));
      if (d_cells <= ins_cells + kSlack) {
        c = cost::kInscribed;
      } else {
        const double f = std::exp(-cfg.cost_scaling_factor * (d_cells - ins_cells) * resolution_m);
        c = std::uint8_t(double(cost::kMaxGraded) * f);  // truncated, as Nav2
      }
    }
    table_[std::size_t(d2)] = c;
  }
  g_ = std::make_unique<std::uint8_t[]>(std::size_t(nx) * std::size_t(ny));
  g2_row_ = std::make_unique<std::int16_t[]>(std::size_t(nx + 2 * radius_));
  d2_row_ = std::make_unique<std::int16_t[]>(std::size_t(nx));
  sq_ = std::make_unique<std::int16_t[]>(std::size_t(cap + 1));
  for (int k = 0; k <= cap; ++k) sq_[std::size_t(k)] = std::int16_t(k * k);
  return true;
}

void InflationLayer::apply(const RollingGrid<std::uint8_t>& src, RollingGrid<std::uint8_t>& dst) {
  assert(grid::same_window(src, dst) && src.nx() == nx_ && src.ny() == ny_);
  const int nx = nx_, ny = ny_, R = radius_;
  const auto cap = std::uint8_t(R + 1);
  const std::size_t unx = std::size_t(nx);
  // Pass 1, down then up: g = vertical distance to the nearest lethal cell in the column, capped.
  // Rows in window order, columns in storage order (columns are independent).
  std::uint8_t* g = g_.get();
  for (int ly = 0; ly < ny; ++ly) {
    const std::uint8_t* s = src.storage_row(ly);
    std::uint8_t* row = g + std::size_t(ly) * unx;
    if (ly == 0) {
      for (std::size_t i = 0; i < unx; ++i) row[i] = s[i] == cost::kLethal ? 0 : cap;
    } else {
      const std::uint8_t* prev = row - unx;
      for (std::size_t i = 0; i < unx; ++i) {
        const auto up = std::uint8_t(std::min<int>(prev[i] + 1, cap));
        row[i] = s[i] == cost::kLethal ? std::uint8_t(0) : up;
      }
    }
  }
  for (int ly = ny - 2; ly >= 0; --ly) {
    std::uint8_t* row = g + std::size_t(ly) * unx;
    const std::uint8_t* next = row + unx;
    for (std::size_t i = 0; i < unx; ++i) {
      row[i] = std::uint8_t(std::min<int>(row[i], next[i] + 1));
    }
  }

  // Pass 2, per row in window column order: the min over the horizontal neighbours.
  const auto far = std::int16_t(int(cap) * int(cap));
  std::int16_t* g2 = g2_row_.get();
  std::int16_t* d2 = d2_row_.get();
  const std::int16_t* sq = sq_.get();
  const std::uint8_t* table = table_.get();
  for (int i = 0; i < R; ++i) g2[i] = g2[R + nx + i] = far;
  const int off = src.column_offset();
  const int head = nx - off;  // window columns [0, head) are storage columns [off, nx)
  for (int ly = 0; ly < ny; ++ly) {
    const std::uint8_t* grow = g + std::size_t(ly) * unx;
    std::uint8_t nearest = cap;
    for (int i = 0; i < nx; ++i) nearest = std::min(nearest, grow[i]);
    std::uint8_t* out = dst.storage_row(ly);
    const std::uint8_t* s = src.storage_row(ly);
    if (nearest >= cap) {  // no lethal cell within R rows: no inflation cost in this row
      if (out != s) std::copy(s, s + unx, out);
      continue;
    }
    std::int16_t* w = g2 + R;  // w[lx] for window column lx
    for (int lx = 0; lx < head; ++lx) w[lx] = sq[grow[off + lx]];
    for (int lx = head; lx < nx; ++lx) w[lx] = sq[grow[lx - head]];
    // Only columns within R of one with a lethal cell within R rows can cost anything: elsewhere
    // d2 is `far`, the table gives 0 and the cell keeps its source value. A wall across the rows
    // (the usual case) leaves a few tens of columns to do, not the row.
    int lo = 0, hi = nx - 1;
    while (w[lo] >= far) ++lo;  // stops: `nearest` above is below the cap
    while (w[hi] >= far) --hi;
    const int a = lo - R > 0 ? lo - R : 0, b = hi + R < nx - 1 ? hi + R : nx - 1;
    for (int lx = a; lx <= b; ++lx) d2[lx] = w[lx];
    for (int dx = 1; dx <= R; ++dx) {
      const std::int16_t dd = sq[dx];
      min_plus_pair(d2 + a, w + a - dx, w + a + dx, dd, b - a + 1);
    }
    // Costs back to storage order, combined with the source cell.
    if (out != s) std::copy(s, s + unx, out);
    const auto combine = [&](int sx, int lx) {
      const std::uint8_t c = table[d2[lx]];
      const std::uint8_t old = s[sx];
      out[sx] = old == cost::kUnknown ? (c > 0 ? c : old) : std::max(old, c);
    };
    // Window column lx is storage column off + lx below `head`, lx - head from there on.
    for (int lx = a; lx <= b && lx < head; ++lx) combine(off + lx, lx);
    for (int lx = a > head ? a : head; lx <= b; ++lx) combine(lx - head, lx);
  }
}

}  // namespace carril::fw
