#include "host_sim/scenario/HypotScreen.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace carril::sim {
namespace {

// Limits at the distance itself and one and two ulps either side (the ties and near-ties the
// squares cannot settle), at 1e-12 relative either side (the margin's edge), and far off, over
// offsets from subnormal to 1e300 (the tests trap overflow): every answer must be hypot's.
TEST(HypotScreenTest, AnswersAsHypotDoesAtTiesMarginsAndExtremes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-1060, 1000);
  int checked = 0, settled_by_squares = 0;
  for (int k = 0; k < 20000; ++k) {
    const double scale = std::ldexp(1.0, k % 4 == 0 ? expo(rng) : expo(rng) / 100);
    const double dx = mant(rng) * scale, dy = (k % 7 == 0 ? 0.0 : mant(rng)) * scale;
    const double h = std::hypot(dx, dy);
    std::vector<double> limits = {h, h * (1 + 1e-12), h * (1 - 1e-12), h * 2, h * 0.5, 1.0, 0.0};
    double l = h, u = h;
    for (int i = 0; i < 2; ++i) {
      l = std::nextafter(l, 0.0);
      u = std::nextafter(u, HUGE_VAL);
      limits.push_back(l);
      limits.push_back(u);
    }
    for (const double lim : limits) {
      ASSERT_EQ(hypot_at_most(dx, dy, lim), h <= lim) << dx << " " << dy << " " << lim;
      if (!hypot_may_be_below_or_at(dx, dy, lim)) {
        ASSERT_FALSE(h <= lim) << dx << " " << dy << " " << lim;
        ++settled_by_squares;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 20000 * 11);
  EXPECT_GT(settled_by_squares, 20000);  // the screen does screen (h * 0.5, and more)
}

}  // namespace
}  // namespace carril::sim
