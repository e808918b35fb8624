// Monte Carlo localisation, the samplers: the odometry motion model's statistics, low-variance
// resampling's expected copies, the alias table's frequencies, the KLD bound and its bin set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "firmware/estimation/KldSampling.hpp"
#include "firmware/estimation/MclRandom.hpp"
#include "firmware/estimation/OdometryMotionModel.hpp"
#include "firmware/estimation/Resampling.hpp"

namespace carril::fw {
namespace {

// The three parts of a sampled motion, recovered from the poses (the inverse of sample()).
struct Parts {
  double rot1, trans, rot2;
};
Parts decompose(const Pose2& from, const Pose2& to) {
  const double dx = to.x - from.x, dy = to.y - from.y;
  const double rot1 = wrap_angle(std::atan2(dy, dx) - from.yaw);
  return {rot1, std::hypot(dx, dy), wrap_angle(to.yaw - from.yaw - rot1)};
}

TEST(MclMotionModel, SamplesHaveTheModelsMeansAndVariances) {
  // Translation noise small enough that no sample drives backwards (its parts would then be
  // recovered with rot1 off by pi): 6 standard deviations.
  OdometryNoise noise{0.05, 0.1, 0.02, 0.005};
  const OdometryMotionModel model(noise);
  const Pose2 from{1.0, -2.0, 0.4}, to{1.3, -1.7, 0.9};
  const OdometryDelta d = model.delta(from, to);
  // The decomposition itself.
  EXPECT_NEAR(d.trans, std::hypot(0.3, 0.3), 1e-12);
  EXPECT_NEAR(d.rot1, kPi / 4 - 0.4, 1e-12);
  EXPECT_NEAR(d.rot2, 0.9 - kPi / 4, 1e-12);
  // Table 5.6's variances.
  const double r1 = d.rot1, t = d.trans, r2 = d.rot2;
  EXPECT_NEAR(d.sd_rot1, std::sqrt(0.05 * r1 * r1 + 0.1 * t * t), 1e-12);
  EXPECT_NEAR(d.sd_trans, std::sqrt(0.02 * t * t + 0.005 * (r1 * r1 + r2 * r2)), 1e-12);
  EXPECT_NEAR(d.sd_rot2, std::sqrt(0.05 * r2 * r2 + 0.1 * t * t), 1e-12);

  // A particle elsewhere moves by the same parts in its own frame.
  const Pose2 start{4.0, 3.0, -2.5};
  MclRng rng(21);
  constexpr int kN = 200000;
  double m[3] = {}, v[3] = {};
  for (int n = 0; n < kN; ++n) {
    const Parts p = decompose(start, OdometryMotionModel::sample(start, d, rng));
    const double e[3] = {p.rot1 - d.rot1, p.trans - d.trans, p.rot2 - d.rot2};
    for (int k = 0; k < 3; ++k) {
      m[k] += e[k];
      v[k] += e[k] * e[k];
    }
  }
  const double sd[3] = {d.sd_rot1, d.sd_trans, d.sd_rot2};
  for (int k = 0; k < 3; ++k) {
    const double mean = m[k] / kN, var = v[k] / kN - mean * mean;
    EXPECT_NEAR(mean, 0.0, 5.0 * sd[k] / std::sqrt(double(kN))) << "part " << k;
    // The variance of a sample variance is 2 sd^4 / N: 5 of its standard deviations.
    EXPECT_NEAR(var, sd[k] * sd[k], 5.0 * sd[k] * sd[k] * std::sqrt(2.0 / kN)) << "part " << k;
  }
}

TEST(MclMotionModel, DrivingBackwardsIsNotAHalfTurn) {
  const OdometryMotionModel model;
  const OdometryDelta fwd = model.delta({0, 0, 0}, {0.3, 0, 0});
  const OdometryDelta back = model.delta({0, 0, 0}, {-0.3, 0, 0});
  EXPECT_NEAR(std::abs(back.rot1), kPi, 1e-12);  // the motion itself is represented exactly
  EXPECT_NEAR(back.sd_rot1, fwd.sd_rot1, 1e-12);
  EXPECT_NEAR(back.sd_trans, fwd.sd_trans, 1e-12);
  EXPECT_NEAR(back.sd_rot2, fwd.sd_rot2, 1e-12);
  // A turn in place has no direction of travel: all of it is rot2.
  const OdometryDelta turn = model.delta({1, 1, 0.2}, {1.001, 1, 0.7});
  EXPECT_EQ(turn.rot1, 0.0);
  EXPECT_NEAR(turn.rot2, 0.5, 1e-12);
}

std::vector<double> random_weights(MclRng& rng, int n) {
  auto w = std::vector<double>(std::size_t(n));
  for (auto& x : w) x = rng.uniform() < 0.3 ? 0.0 : std::exp(4.0 * rng.uniform());
  w[std::size_t(n / 2)] = 30.0;  // one dominant particle
  return w;
}

// Expected copies of particle i are n w_i / sum w, over many random offsets, and every draw is
// within one copy of that (the low-variance property).
TEST(MclResampling, LowVarianceCopiesAreUnbiased) {
  MclRng rng(9);
  for (const int n_out : {50, 37, 200}) {
    const std::vector<double> w = random_weights(rng, 50);
    double total = 0.0;
    for (double x : w) total += x;
    constexpr int kTrials = 20000;
    std::vector<double> copies(w.size(), 0.0);
    auto out = std::vector<int>(std::size_t(n_out));
    for (int t = 0; t < kTrials; ++t) {
      low_variance_resample(w.data(), int(w.size()), n_out, rng.uniform(), out.data());
      std::vector<int> c(w.size(), 0);
      for (int i : out) ++c[std::size_t(i)];
      for (std::size_t i = 0; i < w.size(); ++i) {
        const double expect = n_out * w[i] / total;
        ASSERT_LT(std::abs(c[i] - expect), 1.0) << "particle " << i << " n_out " << n_out;
        copies[i] += c[i];
      }
      ASSERT_TRUE(std::is_sorted(out.begin(), out.end()));
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double expect = n_out * w[i] / total;
      // Per trial the count is floor or ceil of expect: its standard deviation is at most 1/2.
      EXPECT_NEAR(copies[i] / kTrials, expect, 5.0 * 0.5 / std::sqrt(double(kTrials)))
          << "particle " << i << " weight " << w[i] << " n_out " << n_out;
    }
  }
}

TEST(MclResampling, SpreadingOverCallsGivesTheSameDraw) {
  MclRng rng(4);
  const std::vector<double> w = random_weights(rng, 300);
  double total = 0.0;
  for (double x : w) total += x;
  std::vector<int> whole(500), spread(500, -1);
  low_variance_resample(w.data(), 300, 500, 0.37, whole.data());
  LowVarianceResampler r;
  r.begin(w.data(), 300, total, 500, 0.37);
  int calls = 0;
  while (!r.done()) {
    const int used = r.run(7, [&](int j, int i) { spread[std::size_t(j)] = i; });
    ASSERT_LE(used, 7);
    ++calls;
  }
  EXPECT_EQ(spread, whole);
  EXPECT_GT(calls, 50);
}

TEST(MclResampling, AliasDrawsFollowTheWeights) {
  MclRng rng(12);
  const std::vector<double> w = random_weights(rng, 40);
  double total = 0.0;
  for (double x : w) total += x;
  AliasTable t(64);
  t.begin(w.data(), int(w.size()), total);
  int calls = 0;
  while (!t.ready()) {
    t.build(3);
    ++calls;
  }
  EXPECT_GT(calls, 10);  // it was spread
  constexpr int kN = 400000;
  std::vector<int> c(w.size(), 0);
  for (int n = 0; n < kN; ++n) ++c[std::size_t(t.draw(rng))];
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double p = w[i] / total;
    EXPECT_NEAR(c[i], kN * p, 5.0 * std::sqrt(kN * p * (1 - p)) + 1e-9) << "particle " << i;
  }
}

TEST(MclKld, BoundMatchesHandComputedValues) {
  // k = 10, err 0.01, z 0.99: b = 2/81 = 0.0246914, sqrt(b) = 0.1571348,
  // x = 1 - b + 0.99 sqrt(b) = 1.1308720, x^3 = 1.4462405, n = 9 / 0.02 x^3 = 650.81.
  EXPECT_NEAR(kld_bound(10, 0.01, 0.99), 650.81, 0.01);
  // k = 2, err 0.05, z 2.326: b = 2/9, x = 1 - 0.2222222 + 2.326 * 0.4714045 = 1.8742675,
  // n = 1 / 0.1 x^3 = 65.840.
  EXPECT_NEAR(kld_bound(2, 0.05, 2.326), 65.840, 0.001);
  // k = 100, err 0.01, z 0.99: b = 2/891, x = 1.0446596, n = 4950 x^3 = 5643.25.
  EXPECT_NEAR(kld_bound(100, 0.01, 0.99), 5643.25, 0.01);
  EXPECT_EQ(kld_bound(1, 0.01, 0.99), 0.0);
  EXPECT_EQ(kld_bound(0, 0.01, 0.99), 0.0);
  // Rounded up, then kept within [min, max].
  EXPECT_EQ(kld_particles(10, 0.01, 0.99, 100, 5000), 651);
  EXPECT_EQ(kld_particles(1, 0.01, 0.99, 100, 5000), 100);
  EXPECT_EQ(kld_particles(100, 0.01, 0.99, 100, 5000), 5000);
}

TEST(MclKld, BinSetCountsDistinctBinsAndClearsInConstantTime) {
  BinSet s(100);
  EXPECT_GE(s.capacity(), 200);
  EXPECT_TRUE(s.insert(0, 0, 0));
  EXPECT_FALSE(s.insert(0, 0, 0));
  EXPECT_TRUE(s.insert(-1, 0, 0));
  EXPECT_TRUE(s.insert(0, -1, 0));
  EXPECT_TRUE(s.insert(0, 0, 35));
  EXPECT_TRUE(s.insert(1 << 20, -(1 << 20), 7));
  EXPECT_EQ(s.size(), 5);
  s.clear();
  EXPECT_EQ(s.size(), 0);
  EXPECT_TRUE(s.insert(0, 0, 0));
  // A full set (half its slots) refuses new bins instead of looping.
  int added = 0;
  for (int k = 0; k < 1000; ++k) added += s.insert(k, 2 * k, 3) ? 1 : 0;
  EXPECT_EQ(s.size(), s.capacity() / 2);
  EXPECT_EQ(added, s.capacity() / 2 - 1);
}

}  // namespace
}  // namespace carril::fw
