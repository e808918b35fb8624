#include "host_sim/sensors/CameraEffects.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "host_sim/sensors/SaturatingAdd.hpp"

namespace carril::sim {

CameraEffects::CameraEffects(const Scenario& scenario, std::uint64_t seed)
    : exposure_(scenario.robot.camera.exposure),
      intensity_(scenario.glare.intensity),
      radius_px_(scenario.glare.radius_px),
      period_s_(scenario.glare.period_s),
      rate_hz_(scenario.robot.camera.rate_hz) {
  for (int i = 0; i < 256; ++i) {
    lut_[std::size_t(i)] =
        static_cast<std::uint8_t>(std::clamp(std::lround(double(i) * exposure_), 0L, 255L));
  }
  // Its own generator: the glare's row does not move any other draw of the run.
  std::mt19937_64 rng(seed ^ 0x61A4EULL);
  v_ = int(std::lround(std::uniform_real_distribution<double>(0.15, 0.85)(rng) *
                       scenario.robot.camera.height));
  if (intensity_ > 0.0) {
    reach_ = int(std::ceil(3.0 * radius_px_));
    const int side = 2 * reach_ + 1;
    const double k = -0.5 / (radius_px_ * radius_px_);
    patch_.resize(std::size_t(side) * std::size_t(side) * 3);
    for (int dv = -reach_; dv <= reach_; ++dv) {
      for (int du = -reach_; du <= reach_; ++du) {
        const auto level =
            static_cast<std::uint8_t>(std::lround(intensity_ * std::exp(k * (du * du + dv * dv))));
        const std::size_t at =
            (std::size_t(dv + reach_) * std::size_t(side) + std::size_t(du + reach_)) * 3;
        patch_[at] = patch_[at + 1] = patch_[at + 2] = level;
      }
    }
  }
}

int CameraEffects::glare_u(std::uint64_t frame_index, int width) const {
  const double t = double(frame_index) / rate_hz_;
  const double phase = std::fmod(t, period_s_) / period_s_;
  const double f = phase < 0.5 ? 2.0 * phase : 2.0 - 2.0 * phase;  // across, then back
  return int(std::lround(f * double(width - 1)));
}

void CameraEffects::apply(hal::CameraFrame& frame, std::uint64_t frame_index) const {
  const int w = frame.width, h = frame.height;
  std::uint8_t* d = frame.bgr.data();
  if (exposure_ != 1.0) {
    const std::size_t n = std::size_t(w) * std::size_t(h) * 3;
    for (std::size_t i = 0; i < n; ++i) d[i] = lut_[d[i]];
  }
  apply_glare(frame, frame_index);
}

bool CameraEffects::glare_box(std::uint64_t frame_index, int width, int height, int& u0, int& u1,
                              int& v0, int& v1) const {
  if (intensity_ <= 0.0) return false;
  return box_round(glare_u(frame_index, width), width, height, u0, u1, v0, v1);
}

bool CameraEffects::box_round(int uc, int width, int height, int& u0, int& u1, int& v0,
                              int& v1) const {
  u0 = std::max(0, uc - reach_);
  u1 = std::min(width - 1, uc + reach_);
  v0 = std::max(0, v_ - reach_);
  v1 = std::min(height - 1, v_ + reach_);
  return u0 <= u1 && v0 <= v1;
}

void CameraEffects::apply_glare(hal::CameraFrame& frame, std::uint64_t frame_index) const {
  const int w = frame.width, h = frame.height;
  std::uint8_t* d = frame.bgr.data();
  int u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  if (intensity_ <= 0.0) return;
  const int uc = glare_u(frame_index, w), vc = v_, side = 2 * reach_ + 1;
  if (!box_round(uc, w, h, u0, u1, v0, v1)) return;
  // Byte by byte over each row's span (the patch holds every level three times, B, G and R): a
  // saturating add, sixteen bytes at a time.
  const std::size_t n = std::size_t(u1 - u0 + 1) * 3;
  for (int v = v0; v <= v1; ++v) {
    const std::uint8_t* add =
        &patch_[(std::size_t(v - vc + reach_) * std::size_t(side) + std::size_t(u0 - uc + reach_)) *
                3];
    add_saturate(d + (std::size_t(v) * std::size_t(w) + std::size_t(u0)) * 3, add, n);
  }
}

}  // namespace carril::sim
