#pragma once
// KLD-sampling (Fox, "Adapting the sample size in particle filters through KLD-sampling", IJRR
// 2003): enough particles that, with probability 1 - delta, the KL divergence between the
// particle approximation and the true posterior (both as histograms over bins of x, y, yaw) stays
// below err, given that k bins are occupied:
//   n = (k - 1) / (2 err) (1 - 2 / (9 (k - 1)) + sqrt(2 / (9 (k - 1))) z)^3
// with z the standard normal quantile of 1 - delta (Wilson-Hilferty's chi-square approximation).
// The bins are counted in a fixed open-addressing hash set (storage sized at init, cleared in
// O(1) by a generation stamp).
#include <cstddef>
#include <cstdint>
#include <memory>

namespace carril::fw {

// Fox's bound for k occupied bins (0 for k <= 1), not rounded.
double kld_bound(int k, double err, double z);
// The bound rounded up and kept within [min_n, max_n].
int kld_particles(int k, double err, double z, int min_n, int max_n);

class BinSet {
 public:
  BinSet() = default;
  // Room for max_entries distinct bins at a load of at most 1/2 (init time).
  explicit BinSet(int max_entries);

  // Forgets every bin, O(1).
  void clear();
  // Adds bin (bx, by, bt); true when it was not there yet. Bins past the capacity are refused
  // (false) rather than looping: a set sized for the particle count never gets there.
  bool insert(int bx, int by, int bt);
  int size() const { return size_; }
  int capacity() const { return int(mask_ + 1); }

 private:
  std::size_t mask_ = 0;
  int size_ = 0, limit_ = 0;
  std::uint32_t generation_ = 1;
  std::unique_ptr<std::uint64_t[]> keys_;
  std::unique_ptr<std::uint32_t[]> stamps_;  // slot holds a key of this clear() iff == generation_
};

}  // namespace carril::fw
