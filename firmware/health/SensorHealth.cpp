#include "firmware/health/SensorHealth.hpp"

#include "firmware/core/Param.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include "firmware/core/Check.hpp"
#include "firmware/core/Lanes.hpp"

namespace carril::fw {

// ---- Lidar ----

ScanHealth::ScanHealth(const ScanHealthConfig& cfg) : cfg_(cfg) {
  CARRIL_CHECK(cfg.window_scans >= 1 && cfg.window_scans <= kMaxWindow);
}

bool ScanHealth::add(const hal::LaserScan& scan) {
  Count c;
  for (int i = 0; i < scan.count && i < hal::kMaxScanBeams; ++i) {
    const float r = scan.ranges_m[std::size_t(i)];
    // isfinite first: comparing a NaN would raise FE_INVALID. +inf (nothing within range) and
    // -inf (something closer than range_min) are measurements too.
    if (std::isinf(r) ||
        (std::isfinite(r) && r > 0.0F && r >= scan.range_min_m && r <= scan.range_max_m)) {
      ++c.valid;
    }
  }
  c.total = scan.count;
  window_.push(c);
  while (window_.size() > std::size_t(cfg_.window_scans)) {
    Count old;
    window_.pop(old);
  }
  if (window_.size() < std::size_t(cfg_.window_scans)) return true;
  return valid_fraction() >= cfg_.min_valid_fraction;
}

double ScanHealth::valid_fraction() const {
  std::uint64_t valid = 0, total = 0;
  for (std::size_t i = 0; i < window_.size(); ++i) {
    valid += window_[i].valid;
    total += window_[i].total;
  }
  // A scan with no beams at all has nothing valid in it.
  if (window_.empty()) return 1.0;
  return total == 0 ? 0.0 : double(valid) / double(total);
}

// ---- Camera ----

FrameVerdict FrameHealth::add(const hal::CameraFrame& frame, const Pose2& odom) {
  const int step = cfg_.sample_step_px > 0 ? cfg_.sample_step_px : 1;
  // FNV-1a over the samples, in four lanes taken in turn and folded at the end: one chain of
  // multiplies would take its latency per sample. Only equality with the last frame's hash
  // matters, so the lanes' value need not match a one-lane hash. The colour range in byte lanes,
  // four samples at a time (bytes 4i..4i+2 are sample i's B, G, R; byte 4i+3 stays 0).
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::uint64_t h[4] = {0xcbf29ce484222325ULL, 0x84222325cbf29ce4ULL, 0x9ce484222325cbf2ULL,
                        0x2325cbf29ce48422ULL};
  lanes::U8x16 vlo = ~lanes::U8x16{}, vhi = {};  // every byte 255, every byte 0
  const auto word = [](const std::uint8_t* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16;
  };
  const auto word4 = [](const std::uint8_t* p) {  // the same, p[3] must be readable
    std::uint32_t w = 0;
    std::memcpy(&w, p, sizeof w);
    static_assert(std::endian::native == std::endian::little, "B in the low byte");
    return w & 0xFFFFFFU;
  };
  for (int v = step / 2; v < frame.height; v += step) {
    int u = step / 2;
    // Four bytes read per sample, the next pixel's first one masked off: so the group's last
    // sample must not be the row's last pixel.
    for (; u + 3 * step + 1 < frame.width; u += 4 * step) {
      // Built in a register: four stores read back as one load would stall on forwarding.
      const lanes::U32x4 w = {word4(frame.pixel(u, v)), word4(frame.pixel(u + step, v)),
                              word4(frame.pixel(u + 2 * step, v)),
                              word4(frame.pixel(u + 3 * step, v))};
      for (int k = 0; k < 4; ++k) h[k] = (h[k] ^ w[k]) * kPrime;
      const auto b = std::bit_cast<lanes::U8x16>(w);
      vlo = b < vlo ? b : vlo;
      vhi = b > vhi ? b : vhi;
    }
    for (; u < frame.width; u += step) {
      const std::uint8_t* p = frame.pixel(u, v);
      h[0] = (h[0] ^ word(p)) * kPrime;
      for (int c = 0; c < 3; ++c) {
        vlo[c] = p[c] < vlo[c] ? p[c] : vlo[c];
        vhi[c] = p[c] > vhi[c] ? p[c] : vhi[c];
      }
    }
  }
  const std::uint64_t hash = (((h[0] * kPrime ^ h[1]) * kPrime ^ h[2]) * kPrime ^ h[3]) * kPrime;
  int lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0};
  for (int i = 0; i < 16; i += 4) {
    for (int c = 0; c < 3; ++c) {
      lo[c] = vlo[i + c] < lo[c] ? vlo[i + c] : lo[c];
      hi[c] = vhi[i + c] > hi[c] ? vhi[i + c] : hi[c];
    }
  }
  spread_ = 0;
  for (int c = 0; c < 3; ++c) spread_ = hi[c] - lo[c] > spread_ ? hi[c] - lo[c] : spread_;

  const bool changed = !have_hash_ || hash != hash_;
  hash_ = hash;
  have_hash_ = true;
  if (changed) changed_at_ = odom;

  const bool blank = spread_ <= cfg_.blank_tolerance;
  blank_run_ = blank ? blank_run_ + 1 : 0;
  if (blank_run_ >= cfg_.blank_frames) return FrameVerdict::Blank;
  if (blank) return FrameVerdict::Ok;  // one flat colour repeats itself: the blank rule's case
  // The same image again is normal for a robot standing still; not for one that has moved.
  const double moved = (Vec2(odom.x, odom.y) - Vec2(changed_at_.x, changed_at_.y)).norm();
  const double turned = std::fabs(wrap_angle(odom.yaw - changed_at_.yaw));
  if (!changed && (moved > cfg_.frozen_motion_m || turned > cfg_.frozen_turn_rad)) {
    return FrameVerdict::Frozen;
  }
  return FrameVerdict::Ok;
}

// ---- IMU ----

ImuVerdict ImuHealth::add(const hal::ImuSample& s, double t_s, double odom_wz) {
  if (!s.valid) return ImuVerdict::Ok;  // no sample: nothing to judge (not fitted, or starting)
  const bool plausible = std::isfinite(s.roll_rad) && std::isfinite(s.pitch_rad) &&
                         std::isfinite(s.yaw_rate_radps) &&
                         std::fabs(double(s.roll_rad)) <= cfg_.max_tilt_rad &&
                         std::fabs(double(s.pitch_rad)) <= cfg_.max_tilt_rad &&
                         std::fabs(double(s.yaw_rate_radps)) <= cfg_.max_yaw_rate_radps;
  bad_run_ = plausible ? 0 : bad_run_ + 1;
  if (bad_run_ >= cfg_.out_of_range_samples) return ImuVerdict::OutOfRange;
  if (!plausible) return ImuVerdict::Ok;

  // Bit-identical values: a live IMU's noise makes that impossible for long, unless the
  // simulator's noise-free one sees a robot whose motion does not change.
  const bool same_values = have_last_ && s.roll_rad == last_.roll_rad &&
                           s.pitch_rad == last_.pitch_rad &&
                           s.yaw_rate_radps == last_.yaw_rate_radps;
  const bool same_stamp = have_last_ && s.stamp_ns == last_.stamp_ns;
  if (!same_values) {
    same_since_s_ = t_s;
    odom_wz_min_ = odom_wz_max_ = odom_wz;
  } else {
    odom_wz_min_ = odom_wz < odom_wz_min_ ? odom_wz : odom_wz_min_;
    odom_wz_max_ = odom_wz > odom_wz_max_ ? odom_wz : odom_wz_max_;
  }
  if (!same_stamp) stamp_since_s_ = t_s;
  last_ = s;
  have_last_ = true;
  const bool stale = t_s - stamp_since_s_ > cfg_.frozen_s;
  const bool stuck = t_s - same_since_s_ > cfg_.frozen_s &&
                     odom_wz_max_ - odom_wz_min_ > cfg_.frozen_min_turn_change_radps;
  return stale || stuck ? ImuVerdict::Frozen : ImuVerdict::Ok;
}

}  // namespace carril::fw

namespace carril::fw {

std::span<const Param<ScanHealthConfig>> ScanHealthConfig::params() {
  using C = ScanHealthConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, window_scans, "scans", 1, ScanHealth::kMaxWindow,
                   "the lidar's valid-beam window", "0.25 s of scans, 2 to 64"),
      CARRIL_PARAM(C, min_valid_fraction, "(fraction)", 0.0, 1.0,
                   "fewer valid beams over the window: `scanner_blind`"),
  };
  return kParams;
}

Status ScanHealthConfig::validate() const {
  return Checks("health.scan").params(*this, params()).result();
}

std::span<const Param<FrameHealthConfig>> FrameHealthConfig::params() {
  using C = FrameHealthConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, sample_step_px, "px", 1, 64, "the grid of the frame looked at"),
      CARRIL_PARAM(C, blank_tolerance, "levels", 0, 255,
                   "colour spread at or below this: a blank frame"),
      CARRIL_PARAM(C, blank_frames, "frames", 1, 1000, "blank frames in a row: `camera_blank`",
                   "0.2 s of frames, at least 2"),
      CARRIL_PARAM(C, frozen_motion_m, "m", 0.001, 10.0,
                   "the image must change over this much travel ..."),
      CARRIL_PARAM(C, frozen_turn_rad, "rad", 0.001, 6.3,
                   "... or this much turning, else `camera_frozen`"),
  };
  return kParams;
}

Status FrameHealthConfig::validate() const {
  return Checks("health.frame").params(*this, params()).result();
}

std::span<const Param<ImuHealthConfig>> ImuHealthConfig::params() {
  using C = ImuHealthConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, max_tilt_rad, "rad", 0.01, 1.6, "roll or pitch beyond this is implausible"),
      CARRIL_PARAM(C, max_yaw_rate_radps, "rad/s", 0.1, 100.0,
                   "a yaw rate beyond this is implausible", "4 x `limits.max_yaw_rate_radps`"),
      CARRIL_PARAM(C, out_of_range_samples, "samples", 1, 1000,
                   "implausible samples in a row: `imu_out_of_range`"),
      CARRIL_PARAM(C, frozen_s, "s", 0.01, 60.0, "a sample may not repeat longer: `imu_frozen`"),
      CARRIL_PARAM(C, frozen_min_turn_change_radps, "rad/s", 0.001, 10.0,
                   "odometry yaw-rate change a live IMU must follow"),
  };
  return kParams;
}

Status ImuHealthConfig::validate() const {
  return Checks("health.imu").params(*this, params()).result();
}

}  // namespace carril::fw
