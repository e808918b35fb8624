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
    ++blocks_[static_cast<std::size_t>(bin) / kBlockBins];
  }
}

double LatencyStats::percentile_us(double p) const {
  if (count_ == 0) return 0.0;
  // Rank of the sample at quantile p, 1-based (nearest-rank definition).
  auto rank = static_cast<std::uint64_t>(p * double(count_) + 0.999999);
  if (rank < 1) rank = 1;
  if (rank > count_) rank = count_;
  if (rank > count_ - overflow_) return max_us();  // past the histogram
  // The bin is the first whose cumulative count reaches the rank: found block by block, then bin
  // by bin inside the block, so a percentile costs at most 64 + 128 steps, not 8192 (the
  // telemetry task asks for two per task).
  std::uint64_t seen = 0;
  std::size_t b = 0;
  while (seen + blocks_[b] < rank) seen += blocks_[b++];
  for (std::size_t i = b * kBlockBins;; ++i) {
    seen += bins_[i];
    if (seen >= rank) return edge_us(static_cast<int>(i));
  }
}

}  // namespace carril::fw
