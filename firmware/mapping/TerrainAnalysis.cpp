#include "firmware/mapping/TerrainAnalysis.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

namespace {

constexpr float kBig = 1.0e30F;  // "no observed cell" in extrema (never compared as NaN)

int half_side(double radius_m, double res) {
  return int(std::lround(radius_m / res));
}

// atan2(h, z) for h >= 0, z > 0 [rad]: Abramowitz and Stegun 4.4.47 on [0, 1] (error within
// 1e-5 rad, 0.0006 deg, against limits given in whole degrees), the reflection atan(t) = pi/2 -
// atan(1/t) beyond. libm's atan2 was a sixth of the analysis.
double slope_of_normal(double h, double z) {
  const bool swap = h > z;
  const double t = swap ? z / h : h / z;
  const double t2 = t * t;
  const double p =
      t * (0.9998660 + t2 * (-0.3302995 + t2 * (0.1801410 + t2 * (-0.0851330 + t2 * 0.0208351))));
  return swap ? 0.5 * kPi - p : p;
}

}  // namespace

Status TerrainConfig::validate() const {
  return Checks("terrain")
      .range("normal_radius_m", normal_radius_m, 0.01, 2.0, "m")
      .range("step_radius_m", step_radius_m, 0.01, 2.0, "m")
      .range("drop_radius_m", drop_radius_m, 0.0, 5.0, "m")
      .range("min_points", double(min_points), 3.0, 10000.0, "cells")
      .range("min_spread_m", min_spread_m, 0.0, 1.0, "m")
      .range("frontier_min_unseen", frontier_min_unseen, 0.01, 1.0, "")
      .result();
}

bool smallest_eigenvector(double a00, double a01, double a02, double a11, double a12, double a22,
                          double n[3], double& middle_eigenvalue) {
  // The characteristic polynomial f(l) = det(l I - A) = l^3 - c2 l^2 + c1 l - c0 has three real
  // roots. Left of the smallest, f is negative, rising and concave, so Newton's method started
  // there climbs monotonically onto it: no trigonometry (acos and cos were 40 % of the analysis
  // with Smith's closed form), and on terrain, where the smallest eigenvalue is far below the
  // other two, the first step is already close.
  const double c2 = a00 + a11 + a22;
  const double m0 = a11 * a22 - a12 * a12, m1 = a00 * a22 - a02 * a02, m2 = a00 * a11 - a01 * a01;
  const double c1 = m0 + m1 + m2;
  const double c0 = a00 * m0 - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02);
  const double scale = std::fabs(a00) + std::fabs(a11) + std::fabs(a22) + std::fabs(a01) +
                       std::fabs(a02) + std::fabs(a12);
  if (!(scale > 0.0) || !std::isfinite(scale)) return false;
  // A covariance is positive semi-definite: then 0 is at or left of the smallest root (f(0) =
  // -det <= 0, f'(0) = c1 > 0) and one step lands near a small one. Otherwise (rounding made it
  // indefinite, or it is not a covariance) Gershgorin's bound.
  double l = 0.0;
  if (!(c0 >= 0.0 && c1 > 0.0 && a00 >= 0.0 && a11 >= 0.0 && a22 >= 0.0))
    l = std::min({a00 - std::fabs(a01) - std::fabs(a02), a11 - std::fabs(a01) - std::fabs(a12),
                  a22 - std::fabs(a02) - std::fabs(a12)});
  for (int it = 0; it < 100; ++it) {
    const double f = ((l - c2) * l + c1) * l - c0;
    const double df = (3.0 * l - 2.0 * c2) * l + c1;
    if (!(f < 0.0) || !(df > 0.0)) break;  // on the root (or rounding past it)
    const double step = -f / df;
    if (!(step > 1e-16 * scale)) break;
    l += step;
    // Convergence is quadratic: after a step this small the error is below rounding.
    if (step < 1e-8 * scale) break;
  }
  // The other two: sum c2 - l, product c1 - l (c2 - l); the smaller root of that quadratic in a
  // form without cancellation.
  const double s = c2 - l, p = c1 - l * s;
  const double disc = std::sqrt(std::max(0.0, s * s - 4.0 * p));
  middle_eigenvalue = (s + disc) > 0.0 ? 2.0 * p / (s + disc) : 0.0;
  // The relative gap: an (almost) repeated smallest eigenvalue has no preferred direction.
  if (!(middle_eigenvalue - l > 1e-12 * scale)) return false;
  // The eigenvector spans the null space of A - l I: the longest cross product of two rows.
  const double m00 = a00 - l, m11 = a11 - l, m22 = a22 - l;
  const double x0 = a01 * a12 - a02 * m11, y0 = a02 * a01 - m00 * a12, z0 = m00 * m11 - a01 * a01;
  const double x1 = a01 * m22 - a02 * a12, y1 = a02 * a02 - m00 * m22, z1 = m00 * a12 - a01 * a02;
  const double x2 = m11 * m22 - a12 * a12, y2 = a12 * a02 - a01 * m22, z2 = a01 * a12 - m11 * a02;
  const double l0 = x0 * x0 + y0 * y0 + z0 * z0;
  const double l1 = x1 * x1 + y1 * y1 + z1 * z1;
  const double l2 = x2 * x2 + y2 * y2 + z2 * z2;
  double vx = x0, vy = y0, vz = z0, len = l0;
  if (l1 > len) vx = x1, vy = y1, vz = z1, len = l1;
  if (l2 > len) vx = x2, vy = y2, vz = z2, len = l2;
  if (!(len > 1e-300)) return false;
  const double sg = (vz < 0.0 ? -1.0 : 1.0) / std::sqrt(len);
  n[0] = vx * sg;
  n[1] = vy * sg;
  n[2] = vz * sg;
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
  for (auto* p : {&hmax_, &hmin_, &lo_, &neg_hi_, &row_min_, &row_neg_max_, &dmin_, &height_,
                  &slope_, &normal_x_, &normal_y_, &normal_z_, &step_up_, &step_down_, &drop_})
    *p = std::make_unique<float[]>(n);
  const std::size_t scratch =
      std::size_t(std::max(nx, ny)) + 4 * std::size_t(std::max({kn_, ks_, kd_})) + 2;
  scratch_g_ = std::make_unique<float[]>(scratch);
  scratch_h_ = std::make_unique<float[]>(scratch);
  status_ = std::make_unique<TerrainStatus[]>(n);
  obs_ = std::make_unique<std::uint8_t[]>(n);
  for (std::size_t i = 0; i < n; ++i) {
    status_[i] = TerrainStatus::kUnobserved;
    obs_[i] = 0;
  }
  return Status::ok();
}

namespace {

// Sliding minimum (or maximum, through negated input) over windows of 2k + 1 samples, van Herk /
// Gil-Werman: three comparisons per sample whatever k. out[i * os] = min of in[j * is] for j in
// [i - k, i + k] clipped to [0, n); i runs over [o0, o1). g and h hold n + 4k + 1 floats.
void sliding_min(const float* in, std::ptrdiff_t is, int n, int k, int o0, int o1, float* out,
                 std::ptrdiff_t os, float* g, float* h) {
  const int w = 2 * k + 1;
  // Padded sequence a[j] = in[j - k] (kBig outside), j in [o0, o1 + 2k): the windows' span.
  const int j0 = o0, j1 = o1 + 2 * k;
  auto a = [&](int j) {
    const int s = j - k;
    return (s >= 0 && s < n) ? in[std::ptrdiff_t(s) * is] : kBig;
  };
  // Blocks aligned to j0: g is the running min from a block's start, h from its end.
  for (int b = j0; b < j1; b += w) {
    const int e = std::min(j1, b + w);
    float m = kBig;
    for (int j = b; j < e; ++j) g[j - j0] = m = std::min(m, a(j));
    m = kBig;
    for (int j = e - 1; j >= b; --j) h[j - j0] = m = std::min(m, a(j));
  }
  for (int i = o0; i < o1; ++i)
    out[std::ptrdiff_t(i) * os] = std::min(h[i - j0], g[i + 2 * k - j0]);
}

}  // namespace

void TerrainAnalysis::compute(const RollingGrid<ElevationCell>& elevation) {
  compute(elevation, 0, 0, nx_, ny_);
}

void TerrainAnalysis::compute(const RollingGrid<ElevationCell>& elevation, int lx0, int ly0, int w,
                              int h) {
  if (elevation.nx() != nx_ || elevation.ny() != ny_) return;
  origin_cx_ = elevation.origin_cx();
  origin_cy_ = elevation.origin_cy();
  const int x0 = std::clamp(lx0, 0, nx_), y0 = std::clamp(ly0, 0, ny_);
  const int x1 = std::clamp(lx0 + w, x0, nx_), y1 = std::clamp(ly0 + h, y0, ny_);
  rx0_ = x0;
  ry0_ = y0;
  rw_ = x1 - x0;
  rh_ = y1 - y0;
  if (rw_ == 0 || rh_ == 0) return;
  // Each part reads only the margin it needs round the target rectangle (a strip of a few rows
  // must not pay for the drop search's 0.5 m in its plane fits): the moments kI, the step
  // extrema ks, the drop minimum kd; heights are copied for the largest.
  const int kI = std::max(kn_, ks_);
  const int k = std::max(kI, kd_);
  const int ex0 = std::max(0, x0 - k), ey0 = std::max(0, y0 - k);
  const int ex1 = std::min(nx_, x1 + k), ey1 = std::min(ny_, y1 + k);

  // Heights (window order); unobserved cells hold kBig in lo_ and -kBig in -hi (no NaN compares).
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
      lo_[i] = o ? c.height_m : kBig;
      neg_hi_[i] = o ? -c.height_m : kBig;
      if (o && !have_ref) {
        zref = double(c.height_m);
        have_ref = true;
      }
    }
  }

  // Integral images of the moments over the rectangle plus kI; x, y in cells from its corner, z
  // in cells too (an isotropic scale keeps PCA's eigenvectors).
  const int ix0 = std::max(0, x0 - kI), iy0 = std::max(0, y0 - kI);
  const int ix1 = std::min(nx_, x1 + kI), iy1 = std::min(ny_, y1 + kI);
  const int iw = ix1 - ix0 + 1;
  const double inv_res = 1.0 / res_;
  Moments* I = integral_.get();
  for (int i = 0; i < iw; ++i) I[i] = Moments{};
  for (int y = iy0; y < iy1; ++y) {
    Moments run{};
    Moments* above = &I[std::size_t(y - iy0) * std::size_t(iw)];
    Moments* cur = above + iw;
    cur[0] = Moments{};
    const double fy = double(y - iy0);
    for (int x = ix0; x < ix1; ++x) {
      const std::size_t i = index(x, y);
      if (obs_[i]) {
        const double fx = double(x - ix0), fz = (double(height_[i]) - zref) * inv_res;
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
      const Moments& a = above[x - ix0 + 1];
      Moments& o = cur[x - ix0 + 1];
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

  // Step extrema over the (2 ks + 1)^2 box and the frontier drop's row minimum over 2 kd + 1,
  // separable: rows (over the rows the boxes reach), then columns (the rectangle only).
  float* g = scratch_g_.get();
  float* hs = scratch_h_.get();
  const std::ptrdiff_t stride = nx_;
  for (int y = std::max(0, y0 - ks_); y < std::min(ny_, y1 + ks_); ++y) {
    const std::size_t r = index(0, y);
    sliding_min(&lo_[r], 1, nx_, ks_, x0, x1, &row_min_[r], 1, g, hs);
    sliding_min(&neg_hi_[r], 1, nx_, ks_, x0, x1, &row_neg_max_[r], 1, g, hs);
  }
  for (int x = x0; x < x1; ++x) {
    sliding_min(&row_min_[std::size_t(x)], stride, ny_, ks_, y0, y1, &hmin_[std::size_t(x)], stride,
                g, hs);
    sliding_min(&row_neg_max_[std::size_t(x)], stride, ny_, ks_, y0, y1, &hmax_[std::size_t(x)],
                stride, g, hs);
  }
  // Rows y0 - ks .. y1 + ks were written for the columns x0 .. x1 only; the column pass above
  // reads exactly those.
  const bool drops = kd_ > ks_;
  if (drops) {  // row pass only: the column pass runs for frontier cells alone, below
    for (int y = ey0; y < ey1; ++y) {
      const std::size_t r = index(0, y);
      sliding_min(&lo_[r], 1, nx_, kd_, x0, x1, &dmin_[r], 1, g, hs);
    }
  }

  const double min_points = double(config_.min_points);
  const double min_spread = (config_.min_spread_m * inv_res) * (config_.min_spread_m * inv_res);
  const double step_box = double((2 * ks_ + 1) * (2 * ks_ + 1));
  // A frontier has at least this many of its step box's cells observed no more.
  const double frontier_seen_max = step_box - std::ceil(config_.frontier_min_unseen * step_box);
  auto corner = [&](int x, int y) -> const Moments& {
    return I[std::size_t(y - iy0) * std::size_t(iw) + std::size_t(x - ix0)];
  };
  auto box = [&](int xlo, int ylo, int xhi, int yhi, Moments& m) {
    const Moments& a = corner(xlo, ylo);
    const Moments& b = corner(xhi + 1, ylo);
    const Moments& c = corner(xlo, yhi + 1);
    const Moments& d = corner(xhi + 1, yhi + 1);
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
  auto box_count = [&](int xlo, int ylo, int xhi, int yhi) {
    return corner(xhi + 1, yhi + 1).n - corner(xhi + 1, ylo).n - corner(xlo, yhi + 1).n +
           corner(xlo, ylo).n;
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
      step_up_[i] = std::max(0.0F, -hmax_[i] - hc);
      step_down_[i] = std::max(0.0F, hc - hmin_[i]);

      // A frontier: enough of the step box, clipped to the window, is unseen (or beyond the
      // window's edge).
      if (drops && box_count(std::max(0, x - ks_), std::max(0, y - ks_), std::min(nx_ - 1, x + ks_),
                             std::min(ny_ - 1, y + ks_)) <= frontier_seen_max) {
        float mn = kBig;
        for (int j = std::max(0, y - kd_); j <= std::min(ny_ - 1, y + kd_); ++j)
          mn = std::min(mn, dmin_[index(x, j)]);
        drop_[i] = std::max(0.0F, hc - mn);
      }

      Moments m;
      box(std::max(0, x - kn_), std::max(0, y - kn_), std::min(nx_ - 1, x + kn_),
          std::min(ny_ - 1, y + kn_), m);
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
      slope_[i] = float(slope_of_normal(std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1]), nrm[2]));
    }
  }
}

}  // namespace carril::fw
