#pragma once
// The localiser's random numbers: xoshiro256** (Blackman and Vigna) seeded through splitmix64,
// with uniform and Gaussian draws built from integer operations, IEEE basic arithmetic and sqrt
// only (no std:: distributions, whose output is implementation-defined, and no libm log), so a
// seed gives the same stream bit for bit on x86_64 and aarch64, provided a * b + c is not
// contracted into an FMA: the estimation layer builds with -ffp-contract=off (GCC's default for
// C++ is to contract, and aarch64 always has FMA).
#include <cmath>
#include <cstdint>

#include "firmware/estimation/MclMath.hpp"

namespace carril::fw {

class MclRng {
 public:
  explicit MclRng(std::uint64_t seed = 1) { reseed(seed); }

  // Restarts the stream from a seed (any value, 0 included).
  void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& w : s_) w = splitmix64(x);
    has_spare_ = false;
  }

  // Next 64 random bits (xoshiro256**).
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Uniform integer in [0, n), n >= 1, without bias (Lemire's multiply-and-reject).
  std::uint32_t below(std::uint32_t n) {
    std::uint64_t m = std::uint64_t(std::uint32_t(next() >> 32)) * n;
    std::uint32_t low = std::uint32_t(m);
    if (low < n) {
      const std::uint32_t threshold = std::uint32_t(-n) % n;
      while (low < threshold) {
        m = std::uint64_t(std::uint32_t(next() >> 32)) * n;
        low = std::uint32_t(m);
      }
    }
    return std::uint32_t(m >> 32);
  }

  // Standard normal (Marsaglia's polar method; the second value of each pair is kept). The point
  // in the square takes its two coordinates from one 64-bit draw (32 bits each: the noise needs
  // no more).
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0.0, v = 0.0, s = 0.0;
    do {
      const std::uint64_t r = next();
      u = double(std::int32_t(std::uint32_t(r))) * 0x1.0p-31;  // [-1, 1)
      v = double(std::int32_t(std::uint32_t(r >> 32))) * 0x1.0p-31;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * portable_log(s) / s);
    spare_ = v * f;
    has_spare_ = true;
    return u * f;
  }
  // Normal with standard deviation sd [any unit].
  double gaussian(double sd) { return sd * gaussian(); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

  std::uint64_t s_[4] = {};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace carril::fw
