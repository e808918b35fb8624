#pragma once
// Terrain analysis over an elevation window: per observed cell the surface normal and slope from
// a local plane fit, and the step up and step down to its neighbourhood, kept apart (a robot may
// climb 3 cm but drop 10 cm).
//
// The plane fit is PCA (the normal is the eigenvector of the smallest eigenvalue of the
// neighbourhood's 3x3 covariance, as grid_map's normal filter computes it), made O(1) per cell:
// integral images of the point moments (count, x, y, z, xx, xy, yy, xz, yz, zz) give every
// square neighbourhood's covariance from four lookups, and the 3x3 eigenproblem is solved in
// closed form (the smallest root of the characteristic polynomial by Newton steps from a
// Gershgorin bound, no trigonometry; the eigenvector from row cross products).
//
// A step down seen from the upper level hides the ground just beyond the edge (occlusion), so
// the step neighbourhood there holds no lower cell. For such frontier cells (a fifth or more of
// the step neighbourhood unobserved: a shadow, not a single cell between two lidar rings),
// drop_m is the drop to the lowest observed cell within drop_radius_m, across the unseen gap:
// the edge is judged without seeing the ground below it.
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/ElevationCell.hpp"

namespace carril::fw {

struct TerrainConfig {
  double normal_radius_m = 0.15;  // half-side of the square plane-fit neighbourhood [m]
  double step_radius_m = 0.10;    // half-side of the square step neighbourhood [m]
  double drop_radius_m = 0.50;    // half-side of the frontier drop search [m]
  // A cell is a frontier when at least this fraction of its step box is unseen (or beyond the
  // window): a shadow behind an edge, not the odd cell the lidar's rings skipped [0..1].
  double frontier_min_unseen = 0.2;
  int min_points = 6;          // observed cells a plane fit needs [cells]
  double min_spread_m = 0.03;  // RMS spread of those cells across their weakest in-plane axis [m]

  Status validate() const;
  bool operator==(const TerrainConfig&) const = default;
};

enum class TerrainStatus : std::uint8_t {
  kUnobserved = 0,     // no height in the cell
  kNotEnoughData = 1,  // height known, too few or too collinear neighbours for a plane
  kValid = 2,          // normal and slope valid
};

class TerrainAnalysis {
 public:
  // Sizes every per-cell array for an nx x ny window (init time only).
  Status init(const TerrainConfig& config, int nx, int ny, double resolution_m);
  // Analyses the whole window. No allocation.
  void compute(const RollingGrid<ElevationCell>& elevation);
  // Analyses window cells [lx0, lx0 + w) x [ly0, ly0 + h) only (to spread the work over ticks);
  // the other cells keep their values (from the window as it was when they were computed).
  void compute(const RollingGrid<ElevationCell>& elevation, int lx0, int ly0, int w, int h);

  // Results, row-major over the window: index(lx, ly) = ly * nx + lx. The window is the one of
  // the elevation grid at the last compute() (origin_cx/origin_cy, global cell indices).
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double resolution() const { return res_; }
  int origin_cx() const { return origin_cx_; }
  int origin_cy() const { return origin_cy_; }
  std::size_t index(int lx, int ly) const { return std::size_t(ly) * std::size_t(nx_) + lx; }
  // Last computed rectangle (window indices).
  int rect_x0() const { return rx0_; }
  int rect_y0() const { return ry0_; }
  int rect_w() const { return rw_; }
  int rect_h() const { return rh_; }

  const TerrainStatus* status() const { return status_.get(); }
  const float* height_m() const { return height_.get(); }        // copy of the cell height [m]
  const float* slope_rad() const { return slope_.get(); }        // acos(n_z) [rad], valid cells
  const float* normal_x() const { return normal_x_.get(); }      // unit normal, n_z > 0
  const float* normal_y() const { return normal_y_.get(); }      //
  const float* normal_z() const { return normal_z_.get(); }      //
  const float* step_up_m() const { return step_up_.get(); }      // highest neighbour above [m]
  const float* step_down_m() const { return step_down_.get(); }  // lowest neighbour below [m]
  const float* drop_m() const { return drop_.get(); }  // frontier cells: drop across the gap [m]
  const TerrainConfig& config() const { return config_; }

 private:
  struct Moments {
    double n, x, y, z, xx, xy, yy, xz, yz, zz;
  };

  TerrainConfig config_;
  int nx_ = 0, ny_ = 0;
  double res_ = 0.0;
  int kn_ = 0, ks_ = 0, kd_ = 0;  // half-sides [cells]
  int origin_cx_ = 0, origin_cy_ = 0;
  int rx0_ = 0, ry0_ = 0, rw_ = 0, rh_ = 0;
  std::unique_ptr<Moments[]> integral_;  // (nx + 1) x (ny + 1)
  // hmax_ holds the negated maximum (the sliding minimum of -height).
  std::unique_ptr<float[]> hmax_, hmin_, lo_, neg_hi_, row_min_, row_neg_max_, dmin_;
  std::unique_ptr<float[]> scratch_g_, scratch_h_;
  std::unique_ptr<TerrainStatus[]> status_;
  std::unique_ptr<float[]> height_, slope_, normal_x_, normal_y_, normal_z_, step_up_, step_down_,
      drop_;
  std::unique_ptr<std::uint8_t[]> obs_;
};

// Smallest-eigenvalue eigenvector of the symmetric 3x3 matrix [[a00 a01 a02] [. a11 a12]
// [. . a22]] (Newton on the characteristic polynomial); also the middle eigenvalue. Returns false
// when degenerate (the two smallest eigenvalues equal: no preferred normal).
bool smallest_eigenvector(double a00, double a01, double a02, double a11, double a12, double a22,
                          double n[3], double& middle_eigenvalue);

}  // namespace carril::fw
