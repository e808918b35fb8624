#pragma once
// Inflation of lethal cells into graded costs (Nav2's inflation layer):
//   254 on a lethal cell, 253 where d <= inscribed radius,
//   252 * exp(-k (d - inscribed)) (truncated) where d <= inflation radius, nothing beyond,
// with d the distance between cell centres [m] to the nearest lethal cell of the window.
//
// Distances are exact (squared integer cell distances, no chamfer error): a separable Euclidean
// distance transform bounded by the inflation radius R [cells]. Pass 1 runs down and up every
// column (all columns at once, row by row: contiguous and vectorisable) for the vertical distance
// g to the nearest lethal cell, capped at R + 1. Pass 2, per row, takes
//   D(x) = min over |dx| <= R of dx^2 + g(x + dx)^2
// which is the exact squared distance wherever it is <= R^2 (farther cells need no cost). The
// cost is read from a table indexed by D built at init. O(cells * R), branch-free and vectorised
// by the compiler; rows with no lethal cell within R rows are skipped.
#include <cstdint>
#include <memory>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct InflationConfig {
  double inscribed_radius_m = 0.25;  // footprint's inscribed radius (half width of a rectangle) [m]
  double inflation_radius_m = 0.55;  // costs end here [m]
  double cost_scaling_factor = 10.0;  // k in 252 exp(-k (d - inscribed)) [1/m]

  Status validate() const;
  bool operator==(const InflationConfig&) const = default;
};

class InflationLayer {
 public:
  // Largest inflation radius [cells] (keeps squared distances in signed 16 bits: SSE2 has a signed
  // 16-bit min).
  static constexpr int kMaxRadiusCells = 120;

  // Builds the cost table and the scratch rows for grids of nx x ny cells of resolution_m [m]
  // (init time). cfg must have passed validate(); false if the radius exceeds kMaxRadiusCells.
  bool init(const InflationConfig& cfg, int nx, int ny, double resolution_m);

  // Writes the inflated costs of src's lethal cells into dst (same size and origin; src == dst is
  // allowed). Each cell becomes max(src, inflation cost); an unknown cell (255) becomes the
  // inflation cost where that cost is above 0 and stays unknown otherwise. Never allocates.
  void apply(const RollingGrid<std::uint8_t>& src, RollingGrid<std::uint8_t>& dst);

  // The inflation cost of a cell at squared distance d2 [cells^2] from the nearest lethal cell
  // (0 beyond the inflation radius).
  std::uint8_t cost_of_sq_cells(int d2) const { return d2 > max_d2_ ? 0 : table_[d2]; }
  int radius_cells() const { return radius_; }
  const InflationConfig& config() const { return cfg_; }

 private:
  InflationConfig cfg_;
  int nx_ = 0, ny_ = 0;
  int radius_ = 0;                          // R = floor(inflation radius / resolution) [cells]
  int max_d2_ = 0;                          // largest squared distance with a cost entry [cells^2]
  std::unique_ptr<std::uint8_t[]> table_;   // cost by squared distance, max_d2_ + 1 entries
  std::unique_ptr<std::uint8_t[]> g_;       // pass 1: vertical distance, ny rows x nx
  std::unique_ptr<std::int16_t[]> g2_row_;  // pass 2: g^2 of one window row, R padding each side
  std::unique_ptr<std::int16_t[]> d2_row_;  // pass 2: squared distance of one window row
  std::unique_ptr<std::int16_t[]> sq_;      // k^2 for k in [0, R + 1]
};

}  // namespace carril::fw
