#include "firmware/estimation/LikelihoodField.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

Status LikelihoodFieldConfig::validate() const {
  Checks c("localisation");
  c.range("z_hit", z_hit, 0.0, 1.0, "")
      .range("z_rand", z_rand, 0.0, 1.0, "")
      .range("sigma_hit_m", sigma_hit_m, 0.005, 5.0, "m")
      .range("laser_max_range_m", z_max_m, 0.1, 200.0, "m")
      .range("likelihood_max_dist_m", max_dist_m, 0.01, 20.0, "m");
  c.fail_if(!(z_rand > 0.0), "z_rand", "must be > 0 (a beam far from every wall has density 0)");
  c.fail_if(!(z_hit + z_rand <= 1.0 + 1e-9), "z_hit",
            "z_hit + z_rand must be at most 1 (they are mixture weights)");
  return c.result();
}

namespace {

// One row of Felzenszwalb and Huttenlocher's 1D squared distance transform:
// d[q] = min_p (q - p)^2 + f[p]. v, z: scratch of n and n + 1 entries.
void distance_1d(const double* f, int n, double* d, int* v, double* z) {
  int k = 0;
  v[0] = 0;
  z[0] = -1e300;
  z[1] = 1e300;
  for (int q = 1; q < n; ++q) {
    // Pop the parabolas the new one hides (z[0] is below any intersection: the loop ends).
    double s = 0.0;
    for (;;) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = 1e300;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < double(q)) ++k;
    const double dq = double(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

LikelihoodField::LikelihoodField(const LikelihoodFieldConfig& cfg, const OccupancyGrid& map)
    : cfg_(cfg) {
  if (!cfg.validate().is_ok() || map.empty()) return;
  nx_ = map.nx();
  ny_ = map.ny();
  res_ = map.resolution();
  inv_res_ = 1.0 / res_;
  ox_ = map.info().origin_x_m;
  oy_ = map.info().origin_y_m;
  max_dist_ = std::min(cfg.max_dist_m, kMaxDistCells * res_);
  stride_ = std::size_t(nx_) + 2;
  max_gx_ = float(nx_ + 1);
  max_gy_ = float(ny_ + 1);
  const std::size_t n = std::size_t(nx_) * std::size_t(ny_);

  d2_ = std::make_unique<std::uint16_t[]>(n);
  const std::uint8_t* cells = map.data();
  squared_distances(cells, true, d2_.get());
  // With surface distances, an endpoint inside an obstacle is as unlikely as one as far outside
  // it: its cell's distance is to the nearest cell that is not occupied.
  std::unique_ptr<std::uint16_t[]> inside;
  if (cfg.surface_distance) {
    inside = std::make_unique<std::uint16_t[]>(n);
    squared_distances(cells, false, inside.get());
  }

  // The table: log p per distinct squared distance (few), then per cell.
  const float border = float(log_p_of_distance(max_dist_));
  table_ = std::make_unique<float[]>(stride_ * (std::size_t(ny_) + 2));
  std::fill(table_.get(), table_.get() + stride_ * (std::size_t(ny_) + 2), border);
  const int max_cells = int(std::ceil(max_dist_ * inv_res_));
  const int max_d2 = std::min(max_cells * max_cells, 65535);
  auto by_d2 = std::make_unique<float[]>(std::size_t(max_d2) + 1);
  // Between cell centres; to the surface half a cell less (a wall's face is its cells' edge).
  const double shift = cfg.surface_distance ? 0.5 * res_ : 0.0;
  for (int q = 0; q <= max_d2; ++q) {
    const double dist = std::max(0.0, std::sqrt(double(q)) * res_ - shift);
    by_d2[std::size_t(q)] = float(log_p_of_distance(dist));
  }
  for (int j = 0; j < ny_; ++j) {
    float* out = &table_[(std::size_t(j) + 1) * stride_ + 1];
    const std::size_t row = std::size_t(j) * std::size_t(nx_);
    for (int i = 0; i < nx_; ++i) {
      const std::size_t k = row + std::size_t(i);
      const std::uint16_t q = inside && cells[k] == cost::kLethal ? inside[k] : d2_[k];
      out[i] = q <= max_d2 ? by_d2[q] : border;
    }
  }
}

// Squared distances [cells^2] from every cell to the nearest occupied cell (to_occupied) or the
// nearest cell that is not occupied, clamped to 16 bits: a column pass, then the exact row pass.
void LikelihoodField::squared_distances(const std::uint8_t* cells, bool to_occupied,
                                        std::uint16_t* out) const {
  const std::size_t n = std::size_t(nx_) * std::size_t(ny_);
  // Pass 1, along each column (row by row, contiguous): vertical distance [cells] to the nearest
  // target cell, capped where no target is in the column.
  const std::uint32_t cap = std::uint32_t(nx_ + ny_ + 2);
  auto g = std::make_unique<std::uint32_t[]>(n);
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const std::size_t k = std::size_t(j) * std::size_t(nx_) + std::size_t(i);
      const std::uint32_t above = j > 0 ? g[k - std::size_t(nx_)] + 1 : cap;
      const bool target = (cells[k] == cost::kLethal) == to_occupied;
      g[k] = target ? 0 : std::min(above, cap);
    }
  }
  for (int j = ny_ - 2; j >= 0; --j) {
    for (int i = 0; i < nx_; ++i) {
      const std::size_t k = std::size_t(j) * std::size_t(nx_) + std::size_t(i);
      g[k] = std::min(g[k], g[k + std::size_t(nx_)] + 1);
    }
  }
  // Pass 2, along each row: the exact squared distance.
  const int m = std::max(nx_, ny_);
  auto f = std::make_unique<double[]>(std::size_t(m));
  auto d = std::make_unique<double[]>(std::size_t(m));
  auto v = std::make_unique<int[]>(std::size_t(m));
  auto z = std::make_unique<double[]>(std::size_t(m) + 1);
  for (int j = 0; j < ny_; ++j) {
    const std::size_t row = std::size_t(j) * std::size_t(nx_);
    for (int i = 0; i < nx_; ++i) {
      const double gi = double(g[row + std::size_t(i)]);
      f[std::size_t(i)] = gi * gi;
    }
    distance_1d(f.get(), nx_, d.get(), v.get(), z.get());
    for (int i = 0; i < nx_; ++i) {
      out[row + std::size_t(i)] = std::uint16_t(std::min(d[std::size_t(i)], 65535.0));
    }
  }
}

double LikelihoodField::log_p_of_distance(double dist) const {
  const double dd = std::min(dist, max_dist_);
  const double s = cfg_.sigma_hit_m;
  const double hit = std::exp(-0.5 * dd * dd / (s * s)) / (std::sqrt(2.0 * kPi) * s);
  return std::log(cfg_.z_hit * hit + cfg_.z_rand / cfg_.z_max_m);
}

double LikelihoodField::distance(int i, int j) const {
  if (!ok() || i < 0 || j < 0 || i >= nx_ || j >= ny_) return max_dist_;
  const double d2 = double(d2_[std::size_t(j) * std::size_t(nx_) + std::size_t(i)]);
  return std::min(std::sqrt(d2) * res_, max_dist_);
}

double LikelihoodField::distance_at(double x, double y) const {
  const double fx = (x - ox_) * inv_res_, fy = (y - oy_) * inv_res_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < double(nx_) && fy < double(ny_))) return max_dist_;
  return distance(int(fx), int(fy));
}

}  // namespace carril::fw
