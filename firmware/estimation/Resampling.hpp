#pragma once
// The two samplers of a resampling step, both linear in the particle count and resumable, so
// the work can be spread over ticks (each call does at most `budget` units of work, one unit per
// element visited, and returns how many it used).
//
// LowVarianceResampler: Probabilistic Robotics table 4.4 (systematic resampling): n_out pointers
// spaced total / n_out apart from one random offset walk the cumulative weights once; particle i
// gets n_out w_i / total copies in expectation (unbiased) and never more than one off that.
// AMCL instead draws every sample by a linear search of the cumulative weights: quadratic.
//
// AliasTable: Walker's alias method in Vose's O(n) construction: independent draws from the
// weights in O(1) each, used to count KLD bins on an i.i.d. sample (Fox's sequential bound)
// before the low-variance pass draws the set that is kept.
#include <cstdint>
#include <memory>

#include "firmware/estimation/MclRandom.hpp"

namespace carril::fw {

class LowVarianceResampler {
 public:
  // Starts a pass over weights w[0, n_in) (not normalised; total = their sum > 0) that emits
  // n_out indices; u in [0, 1) is the random offset.
  void begin(const double* w, int n_in, double total, int n_out, double u);
  // Emits up to `budget` indices through out(j, i) (output slot j is a copy of input i), in
  // increasing i; returns the units used (indices emitted plus inputs passed).
  template <typename Out>
  int run(int budget, Out&& out) {
    int used = 0;
    while (j_ < n_out_ && used < budget) {
      const double target = offset_ + double(j_) * step_;
      if (target >= cum_ && i_ < n_in_ - 1) {  // round-off may leave cum_ short of total
        cum_ += w_[++i_];
      } else {
        out(j_, i_);
        ++j_;
      }
      ++used;
    }
    return used;
  }
  bool done() const { return j_ >= n_out_; }

 private:
  const double* w_ = nullptr;
  int n_in_ = 0, n_out_ = 0, i_ = 0, j_ = 0;
  double step_ = 0.0, offset_ = 0.0, cum_ = 0.0;
};

// All n_out indices at once (tests, and callers that need no spreading).
void low_variance_resample(const double* w, int n_in, int n_out, double u, int* out);

class AliasTable {
 public:
  AliasTable() = default;
  // Storage for up to max_n weights (init time).
  explicit AliasTable(int max_n);

  // Starts building the table for w[0, n) (total = their sum > 0), n <= max_n.
  void begin(const double* w, int n, double total);
  // Continues the build by up to `budget` units; returns the units used.
  int build(int budget);
  bool ready() const { return phase_ == Phase::Ready; }
  // One index drawn with probability w_i / total (after ready()).
  int draw(MclRng& rng) const {
    const int k = int(rng.below(std::uint32_t(n_)));
    return rng.uniform() < prob_[k] ? k : alias_[k];
  }

 private:
  enum class Phase : std::uint8_t { Idle, Classify, Pair, Finish, Ready };
  Phase phase_ = Phase::Idle;
  const double* w_ = nullptr;
  int n_ = 0, cursor_ = 0, small_ = 0, large_ = 0;  // small_ grows up from 0, large_ down from n
  double scale_ = 0.0;
  std::unique_ptr<double[]> prob_;
  std::unique_ptr<int[]> alias_;
  std::unique_ptr<int[]> work_;  // the small stack [0, small_) and the large stack [large_, n)
};

}  // namespace carril::fw
