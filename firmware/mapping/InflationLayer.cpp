#include "firmware/mapping/InflationLayer.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "firmware/core/Check.hpp"
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
static_assert((InflationLayer::kMaxRadiusCells + 1) * (InflationLayer::kMaxRadiusCells + 1) +
                      InflationLayer::kMaxRadiusCells * InflationLayer::kMaxRadiusCells <=
                  32767,
              "d2 = g^2 + dx^2 must fit an int16");
static_assert(InflationLayer::kMaxRadiusCells + 2 <= 255, "g + 1 <= cap + 1 must fit a byte");

// out[i] = in[i]^2 for n bytes: the squared vertical distances of a row, in window order.
void square_bytes(const std::uint8_t* __restrict in, std::int16_t* __restrict out, int n) {
  for (int i = 0; i < n; ++i) out[i] = std::int16_t(int(in[i]) * int(in[i]));
}

// The first column from `i` on whose w is below `far` (w never exceeds it), or n. Four columns
// a step while all four are far: most of a row is.
int skip_far(const std::int16_t* w, int i, int n, std::int16_t far) {
  std::uint64_t all_far = std::uint16_t(far);
  all_far |= all_far << 16;
  all_far |= all_far << 32;
  for (; i + 4 <= n; i += 4) {
    std::uint64_t four = 0;
    std::memcpy(&four, w + i, sizeof four);
    if (four != all_far) break;
  }
  while (i < n && w[i] >= far) ++i;
  return i;
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
  if (!CARRIL_CHECK(grid::same_window(src, dst) && src.nx() == nx_ && src.ny() == ny_)) return;
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
      // In byte lanes (prev + 1 <= cap + 1 fits in a byte): 16 cells per instruction, not 4.
      for (std::size_t i = 0; i < unx; ++i) {
        const auto up1 = std::uint8_t(prev[i] + 1);
        const std::uint8_t up = up1 < cap ? up1 : cap;
        row[i] = s[i] == cost::kLethal ? std::uint8_t(0) : up;
      }
    }
  }
  for (int ly = ny - 2; ly >= 0; --ly) {
    std::uint8_t* row = g + std::size_t(ly) * unx;
    const std::uint8_t* next = row + unx;
    for (std::size_t i = 0; i < unx; ++i) {
      const auto down1 = std::uint8_t(next[i] + 1);
      row[i] = row[i] < down1 ? row[i] : down1;
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
    // g^2 as a widening multiply the compiler vectorises (cap^2 fits: R <= kMaxRadiusCells).
    square_bytes(grow + off, w, head);
    square_bytes(grow, w + head, nx - head);
    if (out != s) std::copy(s, s + unx, out);
    const auto combine = [&](int sx, int lx) {
      const std::uint8_t c = table[d2[lx]];
      const std::uint8_t old = s[sx];
      out[sx] = old == cost::kUnknown ? (c > 0 ? c : old) : std::max(old, c);
    };
    // Only columns within R of one with a lethal cell within R rows can cost anything: elsewhere
    // d2 is `far`, the table gives 0 and the cell keeps its source value. So each cluster of such
    // columns is done on its own, widened by R (clusters whose widenings touch go together): two
    // walls on either side of the robot leave two bands of a few tens of columns, not the row.
    int lx = 0;
    while (lx < nx) {
      lx = skip_far(w, lx, nx, far);
      if (lx >= nx) break;
      const int lo = lx;
      int hi = lx, gap = 0;
      for (++lx; lx < nx && gap <= 2 * R; ++lx) {
        if (w[lx] < far) {
          hi = lx;
          gap = 0;
        } else {
          ++gap;
        }
      }
      lx = hi + 1;
      const int a = lo - R > 0 ? lo - R : 0, b = hi + R < nx - 1 ? hi + R : nx - 1;
      for (int k = a; k <= b; ++k) d2[k] = w[k];
      for (int dx = 1; dx <= R; ++dx) {
        const std::int16_t dd = sq[dx];
        min_plus_pair(d2 + a, w + a - dx, w + a + dx, dd, b - a + 1);
      }
      // Costs back to storage order: window column k is storage column off + k below `head`,
      // k - head from there on.
      for (int k = a; k <= b && k < head; ++k) combine(off + k, k);
      for (int k = a > head ? a : head; k <= b; ++k) combine(k - head, k);
    }
  }
}

}  // namespace carril::fw
