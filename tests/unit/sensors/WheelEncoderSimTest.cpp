// The simulated wheel encoders' odometry drift: a wrong wheel radius scales every reading by
// 1 + error, slip perturbs each wheel by a Gaussian fraction of the given spread redrawn every
// 0.1 s, one seed gives one sequence of readings, and no drift reads the true wheel exactly.
#include "host_sim/sensors/WheelEncoderSim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace carril::sim {
namespace {

constexpr hal::TimeNs kTickNs = 10'000'000;  // 100 Hz, as the control loop reads them

struct Reading {
  float radps = 0.0F;
  double pos_rad = 0.0;
};

// n ticks of wheel `wheel` turning at a steady 2 rad/s from 0.3 rad.
std::vector<Reading> drive(WheelEncoderSim& enc, int wheel, int n) {
  std::vector<Reading> out;
  for (int k = 0; k < n; ++k) {
    const double t_s = k * 0.01;
    Reading r;
    enc.read(wheel, hal::TimeNs(k) * kTickNs, 2.0F, 0.3 + 2.0 * t_s, r.radps, r.pos_rad);
    out.push_back(r);
  }
  return out;
}

TEST(WheelEncoderSim, ZeroDriftReadsExactlyTheTrueWheel) {
  WheelEncoderSim enc(OdometryErrorSpec{}, 7);
  for (int k = 0; k < 50; ++k) {
    const float true_radps = 1.0F + 0.37F * float(k);
    const double true_pos = 1.0 / 3.0 + 0.123 * k;
    float radps = 0.0F;
    double pos = 0.0;
    enc.read(k % 4, hal::TimeNs(k) * kTickNs, true_radps, true_pos, radps, pos);
    EXPECT_EQ(radps, true_radps);
    EXPECT_EQ(pos, true_pos);
  }
}

TEST(WheelEncoderSim, AWrongRadiusScalesSpeedAndTravelByOnePlusTheError) {
  OdometryErrorSpec spec;
  spec.wheel_radius_error = 0.05;
  WheelEncoderSim enc(spec, 1);
  const std::vector<Reading> r = drive(enc, 2, 200);
  // The first reading is where the wheel is (the count starts there); every increment after it
  // reads 5 % long.
  EXPECT_DOUBLE_EQ(r[0].pos_rad, 0.3);
  for (std::size_t k = 0; k < r.size(); ++k) {
    EXPECT_NEAR(r[k].radps, 2.0 * 1.05, 1e-6) << k;
    EXPECT_NEAR(r[k].pos_rad - 0.3, 1.05 * 2.0 * 0.01 * double(k), 1e-9) << k;
  }
}

TEST(WheelEncoderSim, SlipHasTheGivenSpreadAndIsRedrawnEveryTenthOfASecond) {
  OdometryErrorSpec spec;
  spec.slip = 0.05;
  WheelEncoderSim enc(spec, 3);
  const int windows = 4000;
  const std::vector<Reading> r = drive(enc, 0, windows * 10);  // 10 ticks per 0.1 s
  double sum = 0.0, sum_sq = 0.0;
  int changed = 0;
  for (int w = 0; w < windows; ++w) {
    const double f = double(r[std::size_t(w) * 10].radps) / 2.0;  // this window's factor
    // Constant within the window...
    for (int k = 1; k < 10; ++k) {
      EXPECT_EQ(r[std::size_t(w) * 10 + std::size_t(k)].radps, r[std::size_t(w) * 10].radps);
    }
    // ... and redrawn at its start.
    if (w > 0 && r[std::size_t(w) * 10].radps != r[std::size_t(w) * 10 - 1].radps) ++changed;
    sum += f - 1.0;
    sum_sq += (f - 1.0) * (f - 1.0);
  }
  EXPECT_EQ(changed, windows - 1);
  const double mean = sum / windows;
  const double sd = std::sqrt(sum_sq / windows - mean * mean);
  // 4000 draws: the sample mean is within 4 standard errors (0.05 / sqrt(4000) = 0.0008), the
  // sample spread within 5 % of 0.05.
  EXPECT_NEAR(mean, 0.0, 0.0032);
  EXPECT_NEAR(sd, 0.05, 0.0025);
  // The position integrates the slipping speed: over the whole run it agrees with it.
  double integral = 0.0;
  for (std::size_t k = 1; k < r.size(); ++k) integral += double(r[k].radps) * 0.01;
  EXPECT_NEAR(r.back().pos_rad - r.front().pos_rad, integral, 1e-3);
}

TEST(WheelEncoderSim, TheSameSeedGivesTheSameReadingsAndAnotherSeedOthers) {
  OdometryErrorSpec spec;
  spec.wheel_radius_error = -0.03;
  spec.slip = 0.1;
  WheelEncoderSim a(spec, 11), b(spec, 11), c(spec, 12);
  const std::vector<Reading> ra = drive(a, 1, 300), rb = drive(b, 1, 300), rc = drive(c, 1, 300);
  int differ = 0;
  for (std::size_t k = 0; k < ra.size(); ++k) {
    EXPECT_EQ(ra[k].radps, rb[k].radps) << k;
    EXPECT_EQ(ra[k].pos_rad, rb[k].pos_rad) << k;
    differ += ra[k].radps != rc[k].radps ? 1 : 0;
  }
  EXPECT_GT(differ, 250);
}

}  // namespace
}  // namespace carril::sim
