#pragma once
// The likelihood-field sensor model (Thrun, Burgard and Fox, Probabilistic Robotics 6.4),
// precomputed from the static map at init. A beam endpoint at distance d from the nearest
// occupied cell has the density
//   p(d) = z_hit N(d; 0, sigma_hit) + z_rand / z_max            [1/m]
// with N the normalised Gaussian density (AMCL leaves out its 1 / (sqrt(2 pi) sigma), which
// makes the hit and random terms incommensurate). The table holds log p(d) per cell as a float.
//
// Distances are exact Euclidean distances between cell centres (Felzenszwalb and Huttenlocher's
// separable squared distance transform, integer valued), clamped at max_dist. Unknown cells get
// their distance like free ones, as AMCL's map does; a point off the map counts as max_dist.
// The table has a one-cell border holding the max_dist value, so a lookup clamps its grid
// coordinates into the border and reads one float: no branch.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Status.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

struct LikelihoodFieldConfig {
  double z_hit = 0.95;       // weight of the Gaussian hit term
  double z_rand = 0.05;      // weight of the uniform random term
  double sigma_hit_m = 0.2;  // spread of the hit term [m]
  double z_max_m = 12.0;     // the range the random term is uniform over [m]
  double max_dist_m = 2.0;   // distances are clamped here (and off the map) [m]
  // Distances to obstacles' surfaces (half a cell off the cell centres), and for an endpoint in
  // an occupied cell its depth inside: for a drawn map whose walls fill their cells, a face at
  // the cells' edge. Off (AMCL's): to occupied cells' centres, 0 anywhere inside a thick wall,
  // which lets the estimate slide by half the wall's thickness towards the walls in view.
  bool surface_distance = false;

  Status validate() const;
};

class LikelihoodField {
 public:
  // Largest max_dist in cells (squared distances are kept in 16 bits).
  static constexpr int kMaxDistCells = 255;

  LikelihoodField() = default;
  // Computes the distance transform and the table (init time). cfg must be valid and the map
  // not empty; ok() tells whether it was (max_dist_m is cut to kMaxDistCells cells).
  LikelihoodField(const LikelihoodFieldConfig& cfg, const OccupancyGrid& map);

  bool ok() const { return table_ != nullptr; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double resolution() const { return res_; }
  double origin_x() const { return ox_; }
  double origin_y() const { return oy_; }
  const LikelihoodFieldConfig& config() const { return cfg_; }

  // log p(d) [log(1/m)] at padded grid coordinates: gx = (x - origin_x) / resolution + 1, the
  // same for y (the + 1 skips the border). Any finite value is fine: it is clamped to the border.
  float log_p_padded(float gx, float gy) const {
    // std::max against a member, not a literal 0: GCC then emits maxss (no branch).
    gx = std::min(std::max(zero_, gx), max_gx_);
    gy = std::min(std::max(zero_, gy), max_gy_);
    return table_[std::size_t(int(gy)) * stride_ + std::size_t(int(gx))];
  }
  // The sum of log p over n beam endpoints (bx[k], by[k]) [cells, robot frame] for a robot at
  // padded grid coordinates (gx, gy) heading (c, s) = (cos, sin) of its yaw: the sensor model's
  // whole per-particle work. Four running sums, so the additions do not wait on each other.
  float sum_log_p(float gx, float gy, float c, float s, const float* bx, const float* by,
                  int n) const {
    float acc0 = 0.0F, acc1 = 0.0F, acc2 = 0.0F, acc3 = 0.0F;
    const auto at = [&](int k) {
      return log_p_padded(gx + c * bx[k] - s * by[k], gy + s * bx[k] + c * by[k]);
    };
    int k = 0;
    for (; k + 4 <= n; k += 4) {
      acc0 += at(k);
      acc1 += at(k + 1);
      acc2 += at(k + 2);
      acc3 += at(k + 3);
    }
    for (; k < n; ++k) acc0 += at(k);
    return (acc0 + acc1) + (acc2 + acc3);
  }
  // log p(d) at a world point [m].
  float log_p(double x, double y) const {
    return log_p_padded(float((x - ox_) * inv_res_ + 1.0), float((y - oy_) * inv_res_ + 1.0));
  }
  // Distance [m] from the centre of cell (i, j) to the nearest occupied cell centre, clamped at
  // max_dist (max_dist off the map).
  double distance(int i, int j) const;
  // (The distance functions are to occupied cells' centres whatever surface_distance says.)
  // Distance [m] for the cell a world point falls in.
  double distance_at(double x, double y) const;
  // log p(d) for a distance d [m] (the formula the table holds).
  double log_p_of_distance(double d) const;
  // The largest log p (a beam exactly on an obstacle) and the smallest (max_dist or more).
  double log_p_max() const { return log_p_of_distance(0.0); }
  double log_p_min() const { return log_p_of_distance(max_dist_); }

 private:
  void squared_distances(const std::uint8_t* cells, bool to_occupied, std::uint16_t* out) const;

  LikelihoodFieldConfig cfg_;
  int nx_ = 0, ny_ = 0;
  std::size_t stride_ = 0;  // nx + 2
  double res_ = 0.05, inv_res_ = 20.0, ox_ = 0.0, oy_ = 0.0;
  double max_dist_ = 0.0;  // [m], after the cut to kMaxDistCells
  float max_gx_ = 0.0F, max_gy_ = 0.0F;
  float zero_ = 0.0F;
  std::unique_ptr<float[]> table_;       // (nx + 2) x (ny + 2), border = max_dist
  std::unique_ptr<std::uint16_t[]> d2_;  // nx x ny squared distances [cells^2], clamped
};

}  // namespace carril::fw
