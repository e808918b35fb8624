#pragma once
// The direction of each beam of a laser scan in the sensor frame, cos and sin of
// angle_min + i * angle_increment, worked out again only when the scan's geometry changes: a
// sincos per beam per scan was 7 % of a simulated run. A beam's world direction is this one turned
// by the sensor's yaw (rotate()), two multiplies and an add each way instead of a sincos.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "hal/Types.hpp"

namespace carril::fw {

class BeamDirections {
 public:
  // Brings the table up to date for `scan` (at most kMaxScanBeams beams); returns the beam count.
  int update(const hal::LaserScan& scan) {
    const int n = scan.count < hal::kMaxScanBeams ? int(scan.count) : hal::kMaxScanBeams;
    // Compared by their bits: no floating-point comparison of what may be a NaN.
    const auto min_bits = std::bit_cast<std::uint32_t>(scan.angle_min_rad);
    const auto inc_bits = std::bit_cast<std::uint32_t>(scan.angle_increment_rad);
    if (n != n_ || min_bits != min_bits_ || inc_bits != inc_bits_) {
      for (int i = 0; i < n; ++i) {
        const double a = double(scan.angle_min_rad) + i * double(scan.angle_increment_rad);
        cos_[std::size_t(i)] = std::cos(a);
        sin_[std::size_t(i)] = std::sin(a);
      }
      n_ = n;
      min_bits_ = min_bits;
      inc_bits_ = inc_bits;
      ++builds_;
    }
    return n;
  }
  double cos(int i) const { return cos_[std::size_t(i)]; }  // of beam i's angle [-]
  double sin(int i) const { return sin_[std::size_t(i)]; }  // of beam i's angle [-]
  // Beam i's direction turned by an angle whose cos and sin are (c, s): (cos, sin) of the sum.
  void rotate(int i, double c, double s, double& out_cos, double& out_sin) const {
    out_cos = c * cos_[std::size_t(i)] - s * sin_[std::size_t(i)];
    out_sin = s * cos_[std::size_t(i)] + c * sin_[std::size_t(i)];
  }
  std::uint32_t builds() const { return builds_; }  // times the table was worked out

 private:
  std::array<double, hal::kMaxScanBeams> cos_{}, sin_{};
  std::uint32_t min_bits_ = 0, inc_bits_ = 0;
  int n_ = -1;
  std::uint32_t builds_ = 0;
};

}  // namespace carril::fw
