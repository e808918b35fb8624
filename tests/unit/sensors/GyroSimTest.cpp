// GyroSim: the robot file's bias and noise on the true yaw rate, deterministic for a seed.
#include "host_sim/sensors/GyroSim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace carril::sim {
namespace {

loader::ImuSpec spec(double noise, double bias) {
  loader::ImuSpec s;
  s.gyro_noise_std_radps = noise;
  s.gyro_bias_radps = bias;
  return s;
}

std::vector<float> samples(const loader::ImuSpec& s, std::uint64_t seed, double truth, int n) {
  GyroSim g(s, seed);
  std::vector<float> out;
  for (int i = 0; i < n; ++i) out.push_back(g.read(truth));
  return out;
}

TEST(GyroSimTest, WithoutErrorsTheTruthPassesThrough) {
  for (const float r : samples(spec(0.0, 0.0), 1, 0.7, 10)) EXPECT_EQ(r, 0.7F);
  for (const float r : samples(spec(0.0, 0.002), 1, 0.7, 10)) EXPECT_EQ(r, float(0.702));
}

TEST(GyroSimTest, BiasAndNoiseHaveTheirSize) {
  const std::vector<float> s = samples(spec(0.01, 0.002), 7, 0.5, 20000);
  double sum = 0.0, sq = 0.0;
  for (const float r : s) sum += r;
  const double mean = sum / double(s.size());
  for (const float r : s) sq += (r - mean) * (r - mean);
  const double std = std::sqrt(sq / double(s.size() - 1));
  EXPECT_NEAR(mean, 0.502, 0.0003);  // 4 standard errors (0.01 / sqrt(20000) = 7e-5)
  EXPECT_NEAR(std, 0.01, 0.0003);
}

TEST(GyroSimTest, TheSameSeedGivesTheSameSamplesAndAnotherDiffers) {
  const loader::ImuSpec s = spec(0.003, 0.0005);
  EXPECT_EQ(samples(s, 42, 0.1, 100), samples(s, 42, 0.1, 100));
  EXPECT_NE(samples(s, 42, 0.1, 100), samples(s, 43, 0.1, 100));
}

}  // namespace
}  // namespace carril::sim
