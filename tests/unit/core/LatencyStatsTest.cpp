#include "firmware/core/LatencyStats.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <memory>

namespace carril::fw {
namespace {

constexpr double kBin = 0.25;  // histogram bin width [us]

// LatencyStats holds a 32 KiB histogram: keep it off the test's stack.
std::unique_ptr<LatencyStats> make() {
  return std::make_unique<LatencyStats>();
}

TEST(LatencyStatsTest, EmptyIsZero) {
  auto s = make();
  EXPECT_EQ(s->count(), 0U);
  EXPECT_EQ(s->max_us(), 0.0);
  EXPECT_EQ(s->percentile_us(0.5), 0.0);
  EXPECT_EQ(s->percentile_us(0.99), 0.0);
}

TEST(LatencyStatsTest, PercentilesOfOneToHundredMicroseconds) {
  auto s = make();
  // Add in a shuffled order: the result must not depend on it.
  for (int i = 0; i < 100; ++i) {
    const int us = 1 + (i * 37) % 100;  // 37 is coprime with 100: a permutation of 1..100
    s->add(std::int64_t{us} * 1000);
  }
  EXPECT_EQ(s->count(), 100U);
  EXPECT_DOUBLE_EQ(s->max_us(), 100.0);
  // Nearest rank: p50 is the 50th sample (50 us), p99 the 99th (99 us); reported as the upper
  // edge of their bin, so within one bin above the sample.
  const double p50 = s->percentile_us(0.50);
  EXPECT_GE(p50, 50.0);
  EXPECT_LE(p50, 50.0 + kBin);
  const double p99 = s->percentile_us(0.99);
  EXPECT_GE(p99, 99.0);
  EXPECT_LE(p99, 99.0 + kBin);
  // p100 never exceeds the exact maximum.
  EXPECT_DOUBLE_EQ(s->percentile_us(1.0), 100.0);
  // p0 is the smallest sample.
  const double p0 = s->percentile_us(0.0);
  EXPECT_GE(p0, 1.0);
  EXPECT_LE(p0, 1.0 + kBin);
}

TEST(LatencyStatsTest, MaxIsExactNotBinned) {
  auto s = make();
  s->add(12'345);  // 12.345 us
  s->add(3'001);
  EXPECT_DOUBLE_EQ(s->max_us(), 12.345);
  // A single-bin answer would say 12.5; the percentile is capped at the exact max.
  EXPECT_DOUBLE_EQ(s->percentile_us(1.0), 12.345);
}

TEST(LatencyStatsTest, OverflowFallsBackToMax) {
  auto s = make();
  // 50 samples at 10 us and 50 beyond the 2048 us histogram (3000..3049 us).
  for (int i = 0; i < 50; ++i) s->add(10'000);
  for (int i = 0; i < 50; ++i) s->add(std::int64_t{3000 + i} * 1000);
  EXPECT_EQ(s->count(), 100U);
  EXPECT_DOUBLE_EQ(s->max_us(), 3049.0);
  // The median is still in the histogram.
  EXPECT_GE(s->percentile_us(0.5), 10.0);
  EXPECT_LE(s->percentile_us(0.5), 10.0 + kBin);
  // p99 lies among the overflowed samples: reported as the maximum.
  EXPECT_DOUBLE_EQ(s->percentile_us(0.99), 3049.0);
}

TEST(LatencyStatsTest, HistogramEndIsOverflow) {
  auto s = make();
  s->add(2'048'000);  // exactly 2048 us: the first value past the last bin
  EXPECT_EQ(s->count(), 1U);
  EXPECT_DOUBLE_EQ(s->percentile_us(0.5), 2048.0);
  EXPECT_DOUBLE_EQ(s->max_us(), 2048.0);
}

TEST(LatencyStatsTest, NegativeClampedToZero) {
  auto s = make();
  s->add(-500);
  EXPECT_EQ(s->count(), 1U);
  EXPECT_EQ(s->max_us(), 0.0);
  EXPECT_EQ(s->percentile_us(0.99), 0.0);
}

TEST(LatencyStatsTest, ResetForgetsEverything) {
  auto s = make();
  for (int i = 0; i < 10; ++i) s->add(5'000'000);
  s->reset();
  EXPECT_EQ(s->count(), 0U);
  EXPECT_EQ(s->max_us(), 0.0);
  EXPECT_EQ(s->percentile_us(0.99), 0.0);
  s->add(2'000);
  EXPECT_DOUBLE_EQ(s->percentile_us(0.99), 2.0);  // bin edge 2.25 capped at max 2.0
}

TEST(LatencyStatsTest, WideBinsCoverSlowWork) {
  // 50 us bins reach 409.6 ms: percentiles of 10-100 ms work stay in the histogram.
  auto s = std::make_unique<LatencyStats>(50'000);
  EXPECT_DOUBLE_EQ(s->bin_us(), 50.0);
  for (int ms = 1; ms <= 100; ++ms) s->add(std::int64_t{ms} * 1'000'000);
  EXPECT_GE(s->percentile_us(0.50), 50'000.0);
  EXPECT_LE(s->percentile_us(0.50), 50'000.0 + 50.0);
  EXPECT_GE(s->percentile_us(0.99), 99'000.0);
  EXPECT_LE(s->percentile_us(0.99), 99'000.0 + 50.0);
  // Reset keeps the bin width.
  s->reset();
  EXPECT_DOUBLE_EQ(s->bin_us(), 50.0);
  s->add(30'000'010);
  EXPECT_DOUBLE_EQ(s->percentile_us(0.5), 30'000.01);  // bin edge 30050 capped at the max
}

// The percentile walk starts from the nearer end; it must give exactly what a walk from the
// bottom gives, for any quantile and any spread of samples (including overflow and ties).
double percentile_by_forward_walk(const std::vector<std::int64_t>& samples, double p,
                                  std::int64_t bin_ns) {
  const int bins = LatencyStats::kBins;
  std::vector<std::uint64_t> hist(bins, 0);
  std::int64_t max_ns = 0;
  for (std::int64_t v : samples) {
    v = v < 0 ? 0 : v;
    max_ns = v > max_ns ? v : max_ns;
    if (v / bin_ns < bins) ++hist[std::size_t(v / bin_ns)];
  }
  const double max_us = double(max_ns) / 1e3;
  auto rank = static_cast<std::uint64_t>(p * double(samples.size()) + 0.999999);
  rank = rank < 1 ? 1 : (rank > samples.size() ? samples.size() : rank);
  std::uint64_t seen = 0;
  for (int i = 0; i < bins; ++i) {
    seen += hist[std::size_t(i)];
    if (seen >= rank) {
      const double edge = double(i + 1) * double(bin_ns) / 1e3;
      return edge < max_us ? edge : max_us;
    }
  }
  return max_us;
}

TEST(LatencyStatsTest, EitherEndGivesTheSamePercentileAsAWalkFromTheBottom) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::int64_t bin_ns = trial % 2 == 0 ? 250 : 50'000;
    std::vector<std::int64_t> samples;
    const int n = 1 + int(rng() % 500);
    const std::int64_t spread = std::int64_t(1) << (rng() % 26);  // 1 ns to 33 ms
    for (int i = 0; i < n; ++i) samples.push_back(std::int64_t(rng() % std::uint64_t(spread)));
    if (trial % 5 == 0) samples.push_back(bin_ns * LatencyStats::kBins * 2);  // overflow
    LatencyStats st(bin_ns);
    for (std::int64_t v : samples) st.add(v);
    for (const double p : {0.0, 0.01, 0.3, 0.5, 0.51, 0.9, 0.99, 0.999, 1.0}) {
      ASSERT_EQ(st.percentile_us(p), percentile_by_forward_walk(samples, p, bin_ns))
          << "trial " << trial << " p " << p << " n " << samples.size();
    }
  }
}

}  // namespace
}  // namespace carril::fw
