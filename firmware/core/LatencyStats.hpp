#pragma once
// Compute-time statistics with fixed memory: a histogram of 0.25 us bins up to 2048 us, plus an
// overflow count and the exact maximum. Percentiles are exact to the bin width below 2 ms.
#include <array>
#include <cstdint>

namespace carril::fw {

class LatencyStats {
 public:
  static constexpr int kBins = 8192;
  static constexpr double kBinUs = 0.25;

  void add(std::int64_t ns);
  void reset() { *this = LatencyStats{}; }
  std::uint64_t count() const { return count_; }
  double max_us() const { return double(max_ns_) / 1e3; }
  // p in [0, 1]; upper edge of the bin holding the p-quantile [us]; max_us() past the histogram.
  double percentile_us(double p) const;

 private:
  std::array<std::uint32_t, kBins> bins_{};
  std::uint64_t overflow_ = 0;
  std::uint64_t count_ = 0;
  std::int64_t max_ns_ = 0;
};

}  // namespace carril::fw
