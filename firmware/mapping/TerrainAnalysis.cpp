#include "firmware/mapping/TerrainAnalysis.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

namespace {

constexpr float kBig = 1.0e30F;  // "no observed cell" in extrema (never compared as NaN)

int half_side(double radius_m, double res) {
  return int(std::lround(radius_m / res));
}

}  // namespace

Status TerrainConfig::validate() const {
  return Checks("terrain")
      .range("normal_radius_m", normal_radius_m, 0.01, 2.0, "m")
      .range("step_radius_m", step_radius_m, 0.01, 2.0, "m")
      .range("drop_radius_m", drop_radius_m, 0.0, 5.0, "m")
      .range("min_points", double(min_points), 3.0, 10000.0, "cells")
      .range("min_spread_m", min_spread_m, 0.0, 1.0, "m")
      .result();
}

bool smallest_eigenvector(double a00, double a01, double a02, double a11, double a12, double a22,
                          double n[3], double& middle_eigenvalue) {
  // Eigenvalues of a symmetric 3x3 in closed form (Smith 1961): A = q I + p B, eig(B) = 2 cos.
  const double p1 = a01 * a01 + a02 * a02 + a12 * a12;
  const double q = (a00 + a11 + a22) / 3.0;
  const double b00 = a00 - q, b11 = a11 - q, b22 = a22 - q;
  const double p = std::sqrt((b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1) / 6.0);
  if (!(p > 1e-12 * (1.0 + std::fabs(q)))) return false;  // isotropic: no preferred normal
  const double ip = 1.0 / p;
  const double c00 = b00 * ip, c11 = b11 * ip, c22 = b22 * ip;
  const double c01 = a01 * ip, c02 = a02 * ip, c12 = a12 * ip;
  const double det =
      c00 * (c11 * c22 - c12 * c12) - c01 * (c01 * c22 - c12 * c02) + c02 * (c01 * c12 - c11 * c02);
  const double r = clampd(0.5 * det, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double e1 = q + 2.0 * p * std::cos(phi);
  const double e3 = q + 2.0 * p * std::cos(phi + 2.0 * kPi / 3.0);
  middle_eigenvalue = 3.0 * q - e1 - e3;
  // The eigenvector spans the null space of A - e3 I: the longest cross product of two rows.
  const double m00 = a00 - e3, m11 = a11 - e3, m22 = a22 - e3;
  const double x0 = a01 * a12 - a02 * m11, y0 = a02 * a01 - m00 * a12, z0 = m00 * m11 - a01 * a01;
  const double x1 = a01 * m22 - a02 * a12, y1 = a02 * a02 - m00 * m22, z1 = m00 * a12 - a01 * a02;
  const double x2 = m11 * m22 - a12 * a12, y2 = a12 * a02 - a01 * m22, z2 = a01 * a12 - m11 * a02;
  const double l0 = x0 * x0 + y0 * y0 + z0 * z0;
  const double l1 = x1 * x1 + y1 * y1 + z1 * z1;
  const double l2 = x2 * x2 + y2 * y2 + z2 * z2;
  double vx = x0, vy = y0, vz = z0, l = l0;
  if (l1 > l) vx = x1, vy = y1, vz = z1, l = l1;
  if (l2 > l) vx = x2, vy = y2, vz = z2, l = l2;
  if (!(l > 1e-300)) return false;
  const double s = (vz < 0.0 ? -1.0 : 1.0) / std::sqrt(l);
  n[0] = vx * s;
  n[1] = vy * s;
  n[2] = vz * s;
  return true;
}

Status TerrainAnalysis::init(const TerrainConfig& config, int nx, int ny, double resolution_m) {
  if (Status s = config.validate(); !s) return s;
  if (nx <= 0 || ny <= 0 || !(resolution_m > 0.0))
    return Status::error("terrain: window %d x %d cells at %g m, expected positive sizes", nx, ny,
                         resolution_m);
  config_ = config;
  nx_ = nx;
  ny_ = ny;
  res_ = resolution_m;
  kn_ = std::max(1, half_side(config.normal_radius_m, res_));
  ks_ = std::max(1, half_side(config.step_radius_m, res_));
  kd_ = half_side(config.drop_radius_m, res_);
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  integral_ = std::make_unique<Moments[]>(std::size_t(nx + 1) * std::size_t(ny + 1));
  for (auto* p : {&hmax_, &hmin_, &tmp_max_, &tmp_min_, &dmin_, &height_, &slope_, &normal_x_,
                  &normal_y_, &normal_z_, &step_up_, &step_down_, &drop_})
    *p = std::make_unique<float[]>(n);
  status_ = std::make_unique<TerrainStatus[]>(n);
  obs_ = std::make_unique<std::uint8_t[]>(n);
  for (std::size_t i = 0; i < n; ++i) {
    status_[i] = TerrainStatus::kUnobserved;
    obs_[i] = 0;
  }
  return Status::ok();
}

void TerrainAnalysis::compute(const RollingGrid<ElevationCell>& elevation) {
  compute(elevation, 0, 0, nx_, ny_);
}

// Max and min of the observed heights in the (2k+1)^2 box round each cell of [ex0, ex1) x
// [ey0, ey1), clipped to it, into hmax_/hmin_ (separable: rows, then columns).
void TerrainAnalysis::sliding_extrema(int ex0, int ey0, int ex1, int ey1, int k, float* out_max,
                                      float* out_min) {
  for (int y = ey0; y < ey1; ++y) {
    const std::size_t row = index(0, y);
    for (int x = ex0; x < ex1; ++x) {
      float mx = -kBig, mn = kBig;
      const int lo = std::max(ex0, x - k), hi = std::min(ex1 - 1, x + k);
      for (int i = lo; i <= hi; ++i) {
        if (!obs_[row + std::size_t(i)]) continue;
        const float v = height_[row + std::size_t(i)];
        mx = v > mx ? v : mx;
        mn = v < mn ? v : mn;
      }
      tmp_max_[row + std::size_t(x)] = mx;
      tmp_min_[row + std::size_t(x)] = mn;
    }
  }
  for (int y = ey0; y < ey1; ++y) {
    const int lo = std::max(ey0, y - k), hi = std::min(ey1 - 1, y + k);
    for (int x = ex0; x < ex1; ++x) {
      float mx = -kBig, mn = kBig;
      for (int j = lo; j <= hi; ++j) {
        const std::size_t i = index(x, j);
        mx = tmp_max_[i] > mx ? tmp_max_[i] : mx;
        mn = tmp_min_[i] < mn ? tmp_min_[i] : mn;
      }
      if (out_max) out_max[index(x, y)] = mx;
      out_min[index(x, y)] = mn;
    }
  }
}

void TerrainAnalysis::compute(const RollingGrid<ElevationCell>& elevation, int lx0, int ly0, int w,
                              int h) {
  if (elevation.nx() != nx_ || elevation.ny() != ny_) return;
  origin_cx_ = elevation.origin_cx();
  origin_cy_ = elevation.origin_cy();
  // The target rectangle, and the region E it reads (expanded by the largest neighbourhood).
  const int x0 = std::clamp(lx0, 0, nx_), y0 = std::clamp(ly0, 0, ny_);
  const int x1 = std::clamp(lx0 + w, x0, nx_), y1 = std::clamp(ly0 + h, y0, ny_);
  rx0_ = x0;
  ry0_ = y0;
  rw_ = x1 - x0;
  rh_ = y1 - y0;
  if (rw_ == 0 || rh_ == 0) return;
  const int k = std::max({kn_, ks_, kd_});
  const int ex0 = std::max(0, x0 - k), ey0 = std::max(0, y0 - k);
  const int ex1 = std::min(nx_, x1 + k), ey1 = std::min(ny_, y1 + k);

  // Copy heights (window order) and find a reference height that keeps the moments small.
  const int off = elevation.column_offset();
  double zref = 0.0;
  bool have_ref = false;
  for (int y = ey0; y < ey1; ++y) {
    const ElevationCell* row = elevation.storage_row(y);
    for (int x = ex0; x < ex1; ++x) {
      const ElevationCell& c = row[(off + x) % nx_];
      const std::size_t i = index(x, y);
      const bool o = c.observed() && std::isfinite(c.height_m);
      obs_[i] = o ? 1 : 0;
      height_[i] = o ? c.height_m : 0.0F;
      if (o && !have_ref) {
        zref = double(c.height_m);
        have_ref = true;
      }
    }
  }

  // Integral images of the moments over E; x, y in cells from E's corner, z in cells too (an
  // isotropic scale keeps PCA's eigenvectors).
  const int iw = ex1 - ex0 + 1;
  const double inv_res = 1.0 / res_;
  Moments* I = integral_.get();
  for (int i = 0; i < iw; ++i) I[i] = Moments{};
  for (int y = ey0; y < ey1; ++y) {
    Moments run{};
    Moments* above = &I[std::size_t(y - ey0) * std::size_t(iw)];
    Moments* cur = above + iw;
    cur[0] = Moments{};
    const double fy = double(y - ey0);
    for (int x = ex0; x < ex1; ++x) {
      const std::size_t i = index(x, y);
      if (obs_[i]) {
        const double fx = double(x - ex0), fz = (double(height_[i]) - zref) * inv_res;
        run.n += 1.0;
        run.x += fx;
        run.y += fy;
        run.z += fz;
        run.xx += fx * fx;
        run.xy += fx * fy;
        run.yy += fy * fy;
        run.xz += fx * fz;
        run.yz += fy * fz;
        run.zz += fz * fz;
      }
      const Moments& a = above[x - ex0 + 1];
      Moments& o = cur[x - ex0 + 1];
      o.n = a.n + run.n;
      o.x = a.x + run.x;
      o.y = a.y + run.y;
      o.z = a.z + run.z;
      o.xx = a.xx + run.xx;
      o.xy = a.xy + run.xy;
      o.yy = a.yy + run.yy;
      o.xz = a.xz + run.xz;
      o.yz = a.yz + run.yz;
      o.zz = a.zz + run.zz;
    }
  }

  sliding_extrema(ex0, ey0, ex1, ey1, ks_, hmax_.get(), hmin_.get());
  // Frontier drops need the minimum over the larger box; only if it differs from the step box.
  const bool drops = kd_ > ks_;
  if (drops) {  // row pass only: the column pass runs for frontier cells alone, below
    for (int y = ey0; y < ey1; ++y) {
      const std::size_t row = index(0, y);
      for (int x = ex0; x < ex1; ++x) {
        float mn = kBig;
        const int lo = std::max(ex0, x - kd_), hi = std::min(ex1 - 1, x + kd_);
        for (int i = lo; i <= hi; ++i)
          if (obs_[row + std::size_t(i)] && height_[row + std::size_t(i)] < mn)
            mn = height_[row + std::size_t(i)];
        dmin_[row + std::size_t(x)] = mn;
      }
    }
  }

  const double min_points = double(config_.min_points);
  const double min_spread = (config_.min_spread_m * inv_res) * (config_.min_spread_m * inv_res);
  const double step_box = double((2 * ks_ + 1) * (2 * ks_ + 1));
  auto box = [&](int xlo, int ylo, int xhi, int yhi, Moments& m) {
    const Moments& a = I[std::size_t(ylo - ey0) * std::size_t(iw) + std::size_t(xlo - ex0)];
    const Moments& b = I[std::size_t(ylo - ey0) * std::size_t(iw) + std::size_t(xhi - ex0 + 1)];
    const Moments& c = I[std::size_t(yhi - ey0 + 1) * std::size_t(iw) + std::size_t(xlo - ex0)];
    const Moments& d = I[std::size_t(yhi - ey0 + 1) * std::size_t(iw) + std::size_t(xhi - ex0 + 1)];
    m.n = d.n - b.n - c.n + a.n;
    m.x = d.x - b.x - c.x + a.x;
    m.y = d.y - b.y - c.y + a.y;
    m.z = d.z - b.z - c.z + a.z;
    m.xx = d.xx - b.xx - c.xx + a.xx;
    m.xy = d.xy - b.xy - c.xy + a.xy;
    m.yy = d.yy - b.yy - c.yy + a.yy;
    m.xz = d.xz - b.xz - c.xz + a.xz;
    m.yz = d.yz - b.yz - c.yz + a.yz;
    m.zz = d.zz - b.zz - c.zz + a.zz;
  };

  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = index(x, y);
      step_up_[i] = step_down_[i] = drop_[i] = 0.0F;
      slope_[i] = normal_x_[i] = normal_y_[i] = 0.0F;
      normal_z_[i] = 1.0F;
      if (!obs_[i]) {
        status_[i] = TerrainStatus::kUnobserved;
        continue;
      }
      const float hc = height_[i];
      step_up_[i] = std::max(0.0F, hmax_[i] - hc);
      step_down_[i] = std::max(0.0F, hc - hmin_[i]);

      Moments m;
      if (drops) {
        box(std::max(ex0, x - ks_), std::max(ey0, y - ks_), std::min(ex1 - 1, x + ks_),
            std::min(ey1 - 1, y + ks_), m);
        // A frontier: the step box is clipped by E's border or holds unobserved cells.
        if (m.n < step_box) {
          float mn = kBig;
          for (int j = std::max(ey0, y - kd_); j <= std::min(ey1 - 1, y + kd_); ++j)
            mn = std::min(mn, dmin_[index(x, j)]);
          drop_[i] = std::max(0.0F, hc - mn);
        }
      }

      box(std::max(ex0, x - kn_), std::max(ey0, y - kn_), std::min(ex1 - 1, x + kn_),
          std::min(ey1 - 1, y + kn_), m);
      status_[i] = TerrainStatus::kNotEnoughData;
      if (m.n < min_points) continue;
      const double in = 1.0 / m.n;
      const double mx = m.x * in, my = m.y * in, mz = m.z * in;
      const double cxx = m.xx * in - mx * mx, cxy = m.xy * in - mx * my;
      const double cxz = m.xz * in - mx * mz, cyy = m.yy * in - my * my;
      const double cyz = m.yz * in - my * mz, czz = m.zz * in - mz * mz;
      double nrm[3], mid = 0.0;
      if (!smallest_eigenvector(cxx, cxy, cxz, cyy, cyz, czz, nrm, mid)) continue;
      if (mid < min_spread) continue;  // the cells lie along a line: no plane
      status_[i] = TerrainStatus::kValid;
      normal_x_[i] = float(nrm[0]);
      normal_y_[i] = float(nrm[1]);
      normal_z_[i] = float(nrm[2]);
      slope_[i] = float(std::atan2(std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1]), nrm[2]));
    }
  }
}

}  // namespace carril::fw
