#include "firmware/mapping/ElevationLayer.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

Status ElevationConfig::validate() const {
  Checks c("elevation");
  c.range("resolution_m", resolution_m, 0.005, 1.0, "m")
      .range("size_x_m", size_x_m, 1.0, 200.0, "m")
      .range("size_y_m", size_y_m, 1.0, 200.0, "m")
      .range("min_range_m", min_range_m, 0.0, 10.0, "m")
      .range("max_range_m", max_range_m, 0.5, 200.0, "m")
      .range("noise_sigma_m", noise_sigma_m, 1e-4, 1.0, "m")
      .range("noise_range_coeff", noise_range_coeff, 0.0, 1.0, "1/m")
      .range("gate_sigmas", gate_sigmas, 0.5, 100.0, "sigma")
      .range("gate_offset_m", gate_offset_m, 0.0, 10.0, "m")
      .range("multi_height_noise_m2", multi_height_noise_m2, 0.0, 1.0, "m^2")
      .range("process_noise_m2_per_s", process_noise_m2_per_s, 0.0, 1.0, "m^2/s")
      .range("max_variance_m2", max_variance_m2, 1e-6, 100.0, "m^2")
      .fail_if(!(max_range_m > min_range_m), "max_range_m", "must be above min_range_m");
  const double cells = (size_x_m / resolution_m) * (size_y_m / resolution_m);
  c.fail_if(cells > 16.0e6, "size_x_m", "window above 16 million cells");
  return c.result();
}

Status ElevationLayer::init(const ElevationConfig& config) {
  if (Status s = config.validate(); !s) return s;
  config_ = config;
  const int nx = int(std::lround(config.size_x_m / config.resolution_m));
  const int ny = int(std::lround(config.size_y_m / config.resolution_m));
  if (!grid_.init(nx, ny, config.resolution_m, ElevationCell{}))
    return Status::error("elevation: grid of %d x %d cells could not be made", nx, ny);
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  mark_ = std::make_unique<std::uint32_t[]>(n);
  scan_z_ = std::make_unique<float[]>(n);
  scan_var_ = std::make_unique<float[]>(n);
  touched_ = std::make_unique<std::uint32_t[]>(n);
  for (std::size_t i = 0; i < n; ++i) mark_[i] = 0;
  sweep_ = 0;
  last_stamp_ns_ = -1;
  return Status::ok();
}

void ElevationLayer::add_process_noise(double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  const float add = float(config_.process_noise_m2_per_s * dt_s);
  const float cap = float(config_.max_variance_m2);
  if (!(add > 0.0F)) return;
  // Branch-free so that it vectorises: a sequential pass over the window every sweep.
  for (int ly = 0; ly < grid_.ny(); ++ly) {
    ElevationCell* row = grid_.storage_row(ly);
    for (int i = 0; i < grid_.nx(); ++i) {
      const float v = row[i].variance_m2;
      const float grown = std::min(v + add, cap);
      row[i].variance_m2 = v > 0.0F ? grown : v;
    }
  }
}

void ElevationLayer::fuse(const hal::PointCloud& cloud, const Pose3& sp) {
  if (!begin_sweep(std::int64_t(cloud.stamp_ns), sp)) return;
  bin_points(cloud, 0, cloud.count);
  end_sweep();
}

bool ElevationLayer::begin_sweep(std::int64_t stamp_ns, const Pose3& sp) {
  last_points_ = last_cells_ = 0;
  in_sweep_ = false;
  sweep_stamp_ns_ = stamp_ns;
  if (!std::isfinite(sp.x) || !std::isfinite(sp.y) || !std::isfinite(sp.z) ||
      !std::isfinite(sp.roll) || !std::isfinite(sp.pitch) || !std::isfinite(sp.yaw)) {
    grow_variances_to(stamp_ns);  // time passed all the same
    return false;
  }
  if (++sweep_ == 0) {  // wrapped: old marks could alias the new numbers
    const std::size_t n = std::size_t(grid_.nx()) * std::size_t(grid_.ny());
    for (std::size_t i = 0; i < n; ++i) mark_[i] = 0;
    sweep_ = 1;
  }
  const Mat3 rd = config_.use_imu_attitude ? rotation_of(sp.roll, sp.pitch, sp.yaw)
                                           : rotation_of(0.0, 0.0, sp.yaw);
  for (int i = 0; i < 9; ++i) r_[i] = float(rd(i / 3, i % 3));
  // Floats in the inner loop; positions relative to the window's corner keep them precise.
  tx_ = float((sp.x - grid_.origin_x()) / grid_.resolution());
  ty_ = float((sp.y - grid_.origin_y()) / grid_.resolution());
  tz_ = float(sp.z);
  used_ = touched_count_ = next_touched_ = 0;
  in_sweep_ = true;
  fusing_ = false;
  return true;
}

void ElevationLayer::bin_points(const hal::PointCloud& cloud, std::uint32_t first,
                                std::uint32_t n) {
  if (!in_sweep_ || fusing_) return;  // not begun, or already fusing
  const float inv_res = float(1.0 / grid_.resolution());
  const float r00 = r_[0], r01 = r_[1], r02 = r_[2], r10 = r_[3], r11 = r_[4], r12 = r_[5];
  const float r20 = r_[6], r21 = r_[7], r22 = r_[8];
  const float tx = tx_, ty = ty_, tz = tz_;
  const float min_r2 = float(config_.min_range_m * config_.min_range_m);
  const float max_r2 = float(config_.max_range_m * config_.max_range_m);
  const float s0 = float(config_.noise_sigma_m), s2 = float(config_.noise_range_coeff);
  const int nx = grid_.nx(), ny = grid_.ny();
  const float fnx = float(nx), fny = float(ny);
  const std::uint32_t count = cloud.count < std::uint32_t(hal::kMaxCloudPoints)
                                  ? cloud.count
                                  : std::uint32_t(hal::kMaxCloudPoints);
  const std::uint32_t end = first < count ? first + std::min(n, count - first) : first;
  std::uint32_t used = used_, touched = touched_count_;
  for (std::uint32_t i = first; i < end; ++i) {
    const hal::CloudPoint& p = cloud.points[i];
    const float r2 = p.x * p.x + p.y * p.y + p.z * p.z;
    // NaN or inf makes r2 NaN or inf: both comparisons below are quiet and reject it.
    if (!(std::isgreaterequal(r2, min_r2) && std::islessequal(r2, max_r2))) continue;
    const float gx = (r00 * p.x + r01 * p.y + r02 * p.z) * inv_res + tx;
    const float gy = (r10 * p.x + r11 * p.y + r12 * p.z) * inv_res + ty;
    if (!(gx >= 0.0F && gy >= 0.0F && gx < fnx && gy < fny)) continue;
    const float z = r20 * p.x + r21 * p.y + r22 * p.z + tz;
    const std::uint32_t k = std::uint32_t(int(gy)) * std::uint32_t(nx) + std::uint32_t(int(gx));
    const float sigma = s0 + s2 * r2;
    ++used;
    if (mark_[k] != sweep_) {
      mark_[k] = sweep_;
      scan_z_[k] = z;
      scan_var_[k] = sigma * sigma;
      touched_[touched++] = k;
    } else if (z > scan_z_[k]) {
      scan_z_[k] = z;
      scan_var_[k] = sigma * sigma;
    }
  }
  used_ = used;
  touched_count_ = touched;
}

void ElevationLayer::grow_variances_to(std::int64_t stamp_ns) {
  if (last_stamp_ns_ >= 0 && stamp_ns > last_stamp_ns_)
    add_process_noise(double(stamp_ns - last_stamp_ns_) * 1e-9);
  last_stamp_ns_ = stamp_ns;
}

void ElevationLayer::end_sweep() {
  while (!fuse_step(0xFFFFFFFFU)) {
  }
}

bool ElevationLayer::fuse_step(std::uint32_t max_cells) {
  if (!in_sweep_) return true;
  if (!fusing_) {  // the first step: one sequential pass ages every cell, binning is over
    grow_variances_to(sweep_stamp_ns_);
    fusing_ = true;
    if (touched_count_ > 0) return false;
  }
  const int nx = grid_.nx();
  const std::uint32_t end =
      touched_count_ - next_touched_ > max_cells ? next_touched_ + max_cells : touched_count_;
  const float gate = float(config_.gate_sigmas), offset = float(config_.gate_offset_m);
  const float grow = float(config_.multi_height_noise_m2), cap = float(config_.max_variance_m2);
  const int ocx = grid_.origin_cx(), ocy = grid_.origin_cy();
  for (std::uint32_t t = next_touched_; t < end; ++t) {
    const std::uint32_t k = touched_[t];
    const int lx = int(k % std::uint32_t(nx)), ly = int(k / std::uint32_t(nx));
    ElevationCell& c = grid_.at(ocx + lx, ocy + ly);
    const float zm = scan_z_[k], vm = scan_var_[k];
    if (!c.observed()) {
      c.height_m = zm;
      c.variance_m2 = vm;
      continue;
    }
    const float d = zm - c.height_m;
    const float band = gate * std::sqrt(c.variance_m2) + offset;
    if (d > band) {  // something new stands here: it replaces the old surface
      c.height_m = zm;
      c.variance_m2 = vm;
    } else if (d < -band) {  // far below: doubt the estimate so that it is re-learned
      c.variance_m2 = c.variance_m2 + grow < cap ? c.variance_m2 + grow : cap;
    } else {
      const float v = c.variance_m2, sum = v + vm;
      c.height_m = (vm * c.height_m + v * zm) / sum;
      c.variance_m2 = v * vm / sum;
    }
  }
  next_touched_ = end;
  if (end < touched_count_) return false;
  in_sweep_ = false;
  last_points_ = used_;
  last_cells_ = touched_count_;
  return true;
}

}  // namespace carril::fw
