// The localisation score: convergence time, error after convergence, relocalisation after a
// kidnap.
#include "host_sim/metrics/LocalisationMetrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::sim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

TEST(LocalisationMetrics, ConvergesWhenTheErrorStaysWithinBoundsForGood) {
  LocalisationMetrics m;
  // 1 m off for 2 s, dips within bounds at 1 s for one tick, then within bounds from 2 s on.
  for (int k = 0; k < 500; ++k) {
    const double t = k * 0.01;
    double e = t < 2.0 ? 1.0 : 0.03;
    if (k == 100) e = 0.05;
    m.add(t, e, t < 2.0 ? 0.0 : 1.0 * kDeg);
  }
  const LocalisationScore s = m.score();
  ASSERT_TRUE(s.time_to_converge_s.has_value());
  EXPECT_NEAR(*s.time_to_converge_s, 2.0, 1e-9);
  EXPECT_NEAR(s.rmse_m, 0.03, 1e-12);
  EXPECT_NEAR(s.max_error_m, 0.03, 1e-12);
  EXPECT_NEAR(s.yaw_rmse_deg, 1.0, 1e-9);
  EXPECT_EQ(s.converged_ticks, 300);
}

TEST(LocalisationMetrics, YawOutsideItsBoundIsNotConverged) {
  LocalisationMetrics m;
  for (int k = 0; k < 100; ++k) m.add(k * 0.01, 0.01, (k < 50 ? 6.0 : 4.0) * kDeg);
  EXPECT_NEAR(*m.score().time_to_converge_s, 0.5, 1e-9);
  LocalisationMetrics never;
  for (int k = 0; k < 100; ++k) never.add(k * 0.01, 0.01, 6.0 * kDeg);
  EXPECT_FALSE(never.score().time_to_converge_s.has_value());
  EXPECT_EQ(never.score().converged_ticks, 0);
}

TEST(LocalisationMetrics, KidnapTimesRelocalisationAndExcludesTheLostStretch) {
  LocalisationMetrics m;
  for (int k = 0; k < 1000; ++k) {
    const double t = k * 0.01;
    if (k == 400) m.kidnap(t);
    // Converged from 1 s; kidnapped at 4 s, 3 m off until 6.5 s; then good again.
    const double e = t < 1.0 ? 0.5 : (t < 4.0 ? 0.02 : (t < 6.5 ? 3.0 : 0.04));
    m.add(t, e, 0.0);
  }
  const LocalisationScore s = m.score();
  EXPECT_NEAR(*s.time_to_converge_s, 1.0, 1e-9);
  ASSERT_EQ(s.relocalised_after_s.size(), 1U);
  ASSERT_TRUE(s.relocalised_after_s[0].has_value());
  EXPECT_NEAR(*s.relocalised_after_s[0], 2.5, 1e-9);
  EXPECT_NEAR(s.max_error_m, 0.04, 1e-12);  // the 3 m stretch is not in it
  EXPECT_NEAR(s.rmse_m, std::sqrt((300 * 0.02 * 0.02 + 350 * 0.04 * 0.04) / 650), 1e-12);
}

TEST(LocalisationMetrics, AKidnapNeverRecoveredFromIsNull) {
  LocalisationMetrics m;
  for (int k = 0; k < 200; ++k) {
    if (k == 100) m.kidnap(k * 0.01);
    m.add(k * 0.01, k < 100 ? 0.0 : 2.0, 0.0);
  }
  const LocalisationScore s = m.score();
  ASSERT_EQ(s.relocalised_after_s.size(), 1U);
  EXPECT_FALSE(s.relocalised_after_s[0].has_value());
}

}  // namespace
}  // namespace carril::sim
