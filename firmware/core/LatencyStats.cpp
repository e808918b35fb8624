#include "firmware/core/LatencyStats.hpp"

namespace carril::fw {

void LatencyStats::add(std::int64_t ns) {
  if (ns < 0) ns = 0;
  ++count_;
  if (ns > max_ns_) max_ns_ = ns;
  const std::int64_t bin = ns / bin_ns_;
  if (bin >= kBins) {
    ++overflow_;
  } else {
    ++bins_[static_cast<std::size_t>(bin)];
  }
}

double LatencyStats::percentile_us(double p) const {
  if (count_ == 0) return 0.0;
  // Rank of the sample at quantile p, 1-based (nearest-rank definition).
  auto rank = static_cast<std::uint64_t>(p * double(count_) + 0.999999);
  if (rank < 1) rank = 1;
  if (rank > count_) rank = count_;
  std::uint64_t seen = 0;
  for (int i = 0; i < kBins; ++i) {
    seen += bins_[static_cast<std::size_t>(i)];
    if (seen >= rank) {
      const double edge = double(i + 1) * bin_us();
      return edge < max_us() ? edge : max_us();
    }
  }
  return max_us();
}

}  // namespace carril::fw
