#pragma once
// Compute-time statistics with fixed memory: a histogram of 8192 bins (0.25 us wide by default,
// so up to 2048 us), plus an overflow count and the exact maximum. Percentiles are exact to the
// bin width below the histogram's end. Slow work (tens of ms) takes wider bins.
#include <array>
#include <cstdint>

namespace carril::fw {

class LatencyStats {
 public:
  static constexpr int kBins = 8192;

  LatencyStats() = default;  // 250 ns bins
  // bin_ns: histogram bin width [ns], at least 1 (smaller is taken as 1).
  explicit LatencyStats(std::int64_t bin_ns) : bin_ns_(bin_ns > 0 ? bin_ns : 1) {}

  void add(std::int64_t ns);
  void reset() { *this = LatencyStats{bin_ns_}; }
  double bin_us() const { return double(bin_ns_) / 1e3; }  // [us]
  std::uint64_t count() const { return count_; }
  double max_us() const { return double(max_ns_) / 1e3; }
  // p in [0, 1]; upper edge of the bin holding the p-quantile [us]; max_us() past the histogram.
  double percentile_us(double p) const;

 private:
  // Upper edge of bin i, capped at the maximum [us].
  double edge_us(int i) const {
    const double edge = double(i + 1) * bin_us();
    return edge < max_us() ? edge : max_us();
  }

  static constexpr std::size_t kBlockBins = 128;  // bins per block of the coarse histogram
  std::array<std::uint32_t, kBins> bins_{};
  std::array<std::uint64_t, kBins / kBlockBins> blocks_{};  // sums of bins_, block by block
  std::uint64_t overflow_ = 0;
  std::uint64_t count_ = 0;
  std::int64_t max_ns_ = 0;
  std::int64_t bin_ns_ = 250;
};

}  // namespace carril::fw
