#include "firmware/estimation/KldSampling.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

double kld_bound(int k, double err, double z) {
  if (k <= 1) return 0.0;
  const double km1 = double(k - 1);
  const double b = 2.0 / (9.0 * km1);
  const double x = 1.0 - b + std::sqrt(b) * z;
  return km1 / (2.0 * err) * x * x * x;
}

int kld_particles(int k, double err, double z, int min_n, int max_n) {
  const double n = std::ceil(kld_bound(k, err, z));
  if (!(n < double(max_n))) return max_n;
  return std::max(min_n, int(n));
}

BinSet::BinSet(int max_entries) {
  std::size_t cap = 16;
  while (cap < 2 * std::size_t(std::max(max_entries, 1))) cap *= 2;
  mask_ = cap - 1;
  limit_ = int(cap / 2);
  keys_ = std::make_unique<std::uint64_t[]>(cap);
  stamps_ = std::make_unique<std::uint32_t[]>(cap);  // zero: empty for generation 1 on
}

void BinSet::clear() {
  size_ = 0;
  if (++generation_ == 0) {  // wrapped after 4 billion clears: reset the stamps once
    std::fill(stamps_.get(), stamps_.get() + mask_ + 1, 0U);
    generation_ = 1;
  }
}

bool BinSet::insert(int bx, int by, int bt) {
  // 21 bits per coordinate: bins of 5 cm reach +-52 km, far beyond any map.
  const auto field = [](int v) { return std::uint64_t(std::uint32_t(v) & 0x1FFFFFU); };
  const std::uint64_t key = field(bx) | (field(by) << 21) | (field(bt) << 42);
  std::size_t slot = std::size_t((key * 0x9E3779B97F4A7C15ULL) >> 32) & mask_;
  for (;;) {
    if (stamps_[slot] != generation_) {
      if (size_ >= limit_) return false;
      stamps_[slot] = generation_;
      keys_[slot] = key;
      ++size_;
      return true;
    }
    if (keys_[slot] == key) return false;
    slot = (slot + 1) & mask_;
  }
}

}  // namespace carril::fw
