#include "firmware/mapping/ElevationLayer.hpp"

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
  for (int ly = 0; ly < grid_.ny(); ++ly) {
    ElevationCell* row = grid_.storage_row(ly);
    for (int i = 0; i < grid_.nx(); ++i) {
      float& v = row[i].variance_m2;
      if (v > 0.0F) v = v + add < cap ? v + add : cap;
    }
  }
}

void ElevationLayer::fuse(const hal::PointCloud& cloud, const Pose3& sp) {
  if (last_stamp_ns_ >= 0 && std::int64_t(cloud.stamp_ns) > last_stamp_ns_)
    add_process_noise(double(std::int64_t(cloud.stamp_ns) - last_stamp_ns_) * 1e-9);
  last_stamp_ns_ = std::int64_t(cloud.stamp_ns);
  last_points_ = last_cells_ = 0;
  if (!std::isfinite(sp.x) || !std::isfinite(sp.y) || !std::isfinite(sp.z) ||
      !std::isfinite(sp.roll) || !std::isfinite(sp.pitch) || !std::isfinite(sp.yaw))
    return;

  if (++sweep_ == 0) {  // wrapped: old marks could alias the new numbers
    const std::size_t n = std::size_t(grid_.nx()) * std::size_t(grid_.ny());
    for (std::size_t i = 0; i < n; ++i) mark_[i] = 0;
    sweep_ = 1;
  }
  const Mat3 rd = config_.use_imu_attitude ? rotation_of(sp.roll, sp.pitch, sp.yaw)
                                           : rotation_of(0.0, 0.0, sp.yaw);
  // Floats in the inner loop; positions relative to the window's corner keep them precise.
  const float inv_res = float(1.0 / grid_.resolution());
  const float r00 = float(rd(0, 0)), r01 = float(rd(0, 1)), r02 = float(rd(0, 2));
  const float r10 = float(rd(1, 0)), r11 = float(rd(1, 1)), r12 = float(rd(1, 2));
  const float r20 = float(rd(2, 0)), r21 = float(rd(2, 1)), r22 = float(rd(2, 2));
  const float tx = float((sp.x - grid_.origin_x()) / grid_.resolution());
  const float ty = float((sp.y - grid_.origin_y()) / grid_.resolution());
  const float tz = float(sp.z);
  const float min_r2 = float(config_.min_range_m * config_.min_range_m);
  const float max_r2 = float(config_.max_range_m * config_.max_range_m);
  const float s0 = float(config_.noise_sigma_m), s2 = float(config_.noise_range_coeff);
  const int nx = grid_.nx(), ny = grid_.ny();
  const float fnx = float(nx), fny = float(ny);
  const std::uint32_t count = cloud.count < std::uint32_t(hal::kMaxCloudPoints)
                                  ? cloud.count
                                  : std::uint32_t(hal::kMaxCloudPoints);
  std::uint32_t used = 0, touched = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
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

  const float gate = float(config_.gate_sigmas), offset = float(config_.gate_offset_m);
  const float grow = float(config_.multi_height_noise_m2), cap = float(config_.max_variance_m2);
  const int ocx = grid_.origin_cx(), ocy = grid_.origin_cy();
  for (std::uint32_t t = 0; t < touched; ++t) {
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
  last_points_ = used;
  last_cells_ = touched;
}

}  // namespace carril::fw
