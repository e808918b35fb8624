#include "firmware/core/BeamDirections.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace carril::fw {
namespace {

std::unique_ptr<hal::LaserScan> scan_of(int n, float min_rad, float inc_rad) {
  auto s = std::make_unique<hal::LaserScan>();
  s->count = std::uint16_t(n);
  s->angle_min_rad = min_rad;
  s->angle_increment_rad = inc_rad;
  return s;
}

TEST(BeamDirectionsTest, HoldsEachBeamsCosAndSinAsTheScanGivesIt) {
  BeamDirections d;
  const auto s = scan_of(360, -3.14159F, 0.0174533F);
  EXPECT_EQ(d.update(*s), 360);
  for (int i = 0; i < 360; ++i) {
    const double a = double(s->angle_min_rad) + i * double(s->angle_increment_rad);
    EXPECT_EQ(d.cos(i), std::cos(a)) << i;  // bit for bit: what the loops computed before
    EXPECT_EQ(d.sin(i), std::sin(a)) << i;
  }
}

TEST(BeamDirectionsTest, IsWorkedOutAgainOnlyWhenTheGeometryChanges) {
  BeamDirections d;
  auto s = scan_of(100, -1.0F, 0.02F);
  d.update(*s);
  d.update(*s);
  EXPECT_EQ(d.builds(), 1U);
  s->angle_increment_rad = 0.021F;
  d.update(*s);
  EXPECT_EQ(d.builds(), 2U);
  EXPECT_DOUBLE_EQ(d.cos(99), std::cos(-1.0 + 99 * double(0.021F)));
  s->angle_min_rad = -1.1F;
  d.update(*s);
  s->count = 50;
  d.update(*s);
  EXPECT_EQ(d.builds(), 4U);
  // A NaN geometry is compared by its bits: no floating-point trap, built once.
  s->angle_min_rad = std::numeric_limits<float>::quiet_NaN();
  d.update(*s);
  d.update(*s);
  EXPECT_EQ(d.builds(), 5U);
}

TEST(BeamDirectionsTest, CountIsCappedAtTheLargestScan) {
  BeamDirections d;
  const auto s = scan_of(hal::kMaxScanBeams + 10, 0.0F, 0.001F);
  EXPECT_EQ(d.update(*s), hal::kMaxScanBeams);
}

TEST(BeamDirectionsTest, RotateGivesTheDirectionOfTheSumOfTheAngles) {
  BeamDirections d;
  const auto s = scan_of(64, -2.0F, 0.0625F);
  d.update(*s);
  for (const double yaw : {-3.0, -0.4, 0.0, 1.3, 3.1}) {
    for (int i = 0; i < 64; ++i) {
      double c = 0.0, sn = 0.0;
      d.rotate(i, std::cos(yaw), std::sin(yaw), c, sn);
      const double a = yaw + double(s->angle_min_rad) + i * double(s->angle_increment_rad);
      EXPECT_NEAR(c, std::cos(a), 1e-15) << yaw << " " << i;
      EXPECT_NEAR(sn, std::sin(a), 1e-15) << yaw << " " << i;
    }
  }
}

}  // namespace
}  // namespace carril::fw
