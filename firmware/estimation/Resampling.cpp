#include "firmware/estimation/Resampling.hpp"

#include <algorithm>

namespace carril::fw {

void LowVarianceResampler::begin(const double* w, int n_in, double total, int n_out, double u) {
  w_ = w;
  n_in_ = n_in;
  n_out_ = n_out;
  step_ = total / double(n_out);
  offset_ = u * step_;
  i_ = 0;
  j_ = 0;
  cum_ = w[0];
}

void low_variance_resample(const double* w, int n_in, int n_out, double u, int* out) {
  double total = 0.0;
  for (int i = 0; i < n_in; ++i) total += w[i];
  LowVarianceResampler r;
  r.begin(w, n_in, total, n_out, u);
  while (!r.done()) r.run(1 << 30, [out](int j, int i) { out[j] = i; });
}

AliasTable::AliasTable(int max_n) {
  const auto n = std::size_t(std::max(max_n, 1));
  prob_ = std::make_unique<double[]>(n);
  alias_ = std::make_unique<int[]>(n);
  work_ = std::make_unique<int[]>(n);
}

void AliasTable::begin(const double* w, int n, double total) {
  w_ = w;
  n_ = n;
  scale_ = double(n) / total;
  cursor_ = 0;
  small_ = 0;
  large_ = n;
  phase_ = Phase::Classify;
}

int AliasTable::build(int budget) {
  int used = 0;
  if (phase_ == Phase::Classify) {
    while (cursor_ < n_ && used < budget) {
      const double p = w_[cursor_] * scale_;
      prob_[cursor_] = p;
      alias_[cursor_] = cursor_;
      // Written to both stacks, kept by one (no branch to mispredict on random weights). The
      // write to the other lands on a free slot: the stacks never meet before the end.
      const int is_small = p < 1.0 ? 1 : 0;
      work_[small_] = cursor_;
      work_[large_ - 1] = cursor_;
      small_ += is_small;
      large_ -= 1 - is_small;
      ++cursor_;
      ++used;
    }
    if (cursor_ == n_) phase_ = Phase::Pair;
  }
  if (phase_ == Phase::Pair) {
    // Each pairing finishes one small entry: it keeps prob, its excess goes to a large one.
    while (small_ > 0 && large_ < n_ && used < budget) {
      const int l = work_[--small_];
      const int g = work_[large_];
      alias_[l] = g;
      prob_[g] = (prob_[g] + prob_[l]) - 1.0;
      if (prob_[g] < 1.0) {  // g moves from the large stack to the small one
        ++large_;
        work_[small_++] = g;
      }
      ++used;
    }
    if (small_ == 0 || large_ == n_) {
      phase_ = Phase::Finish;
      cursor_ = 0;
    }
  }
  if (phase_ == Phase::Finish) {
    // What is left on either stack is 1 up to round-off.
    while (small_ > 0 && used < budget) {
      prob_[work_[--small_]] = 1.0;
      ++used;
    }
    while (large_ < n_ && used < budget) {
      prob_[work_[large_++]] = 1.0;
      ++used;
    }
    if (small_ == 0 && large_ == n_) phase_ = Phase::Ready;
  }
  return used;
}

}  // namespace carril::fw
