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
  const std::uint64_t in_bins = count_ - overflow_;
  if (rank > in_bins) return max_us();  // past the histogram
  // The bin is the first whose cumulative count reaches the rank. Walked from whichever end is
  // nearer in rank: from the bottom for the median, from the bin of the maximum down for the
  // tail (p99), so a percentile costs a few bins, not 8192 (the telemetry task asks for many).
  if (rank <= in_bins / 2) {
    std::uint64_t seen = 0;
    for (int i = 0; i < kBins; ++i) {
      seen += bins_[static_cast<std::size_t>(i)];
      if (seen >= rank) return edge_us(i);
    }
    return max_us();
  }
  const std::int64_t max_bin = max_ns_ / bin_ns_;
  int i = max_bin < kBins - 1 ? static_cast<int>(max_bin) : kBins - 1;
  std::uint64_t through_i = in_bins;  // samples in bins 0..i (none lie above the maximum)
  while (i > 0 && through_i - bins_[static_cast<std::size_t>(i)] >= rank) {
    through_i -= bins_[static_cast<std::size_t>(i)];
    --i;
  }
  return edge_us(i);
}

}  // namespace carril::fw
