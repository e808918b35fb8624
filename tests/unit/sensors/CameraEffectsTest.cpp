// Exposure scales every level (clipped at 255); glare brightens a patch that sweeps across the
// image and back once per period; neither touches a frame when off.
#include "host_sim/sensors/CameraEffects.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

Scenario scenario(const char* camera, const char* glare) {
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml, R"(
name: light
duration_s: 1
robot: {preset: campero%s}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[0, 0], [5, 0]]}]
%s
)",
                camera, glare);
  return test::load_text(yaml);
}

std::unique_ptr<hal::CameraFrame> grey(int w, int h, std::uint8_t level) {
  auto f = std::make_unique<hal::CameraFrame>();
  f->width = std::uint16_t(w);
  f->height = std::uint16_t(h);
  std::fill(f->bgr.begin(), f->bgr.begin() + w * h * 3, level);
  return f;
}

TEST(CameraEffectsTest, NothingIsDoneWhenOff) {
  const CameraEffects e(scenario("", ""), 1);
  EXPECT_FALSE(e.any());
}

TEST(CameraEffectsTest, ExposureScalesLevelsAndClips) {
  const CameraEffects e(scenario(", camera: {exposure: 1.5}", ""), 1);
  ASSERT_TRUE(e.any());
  auto f = grey(640, 480, 100);
  f->bgr[0] = 200;
  e.apply(*f, 0);
  EXPECT_EQ(f->bgr[0], 255);
  EXPECT_EQ(f->bgr[1], 150);
  EXPECT_EQ(f->bgr[640 * 480 * 3 - 1], 150);
}

TEST(CameraEffectsTest, GlareBrightensAPatchThatSweeps) {
  // campero's camera: 30 Hz, 640 x 480.
  const CameraEffects e(scenario("", "glare: {intensity: 100, radius_px: 20, period_s: 2}"), 3);
  ASSERT_TRUE(e.any());
  const int v = e.glare_v();
  EXPECT_GE(v, 0.15 * 480 - 1);
  EXPECT_LE(v, 0.85 * 480 + 1);
  // Frame 15 (0.5 s, a quarter period): half way across.
  EXPECT_EQ(e.glare_u(15, 640), 320);  // 319.5, rounded
  EXPECT_EQ(e.glare_u(30, 640), 639);  // at the right edge after half a period
  EXPECT_EQ(e.glare_u(60, 640), 0);    // back after a period
  auto f = grey(640, 480, 50);
  e.apply(*f, 15);
  const auto level = [&](int u, int vv) { return int(f->pixel(u, vv)[1]); };
  // A Gaussian of 20 px round (320, glare_v).
  const auto expected = [&](int u, int vv) {
    const double du = u - 320.0, dv = vv - e.glare_v();
    return 50 + int(std::lround(100.0 * std::exp(-(du * du + dv * dv) / 800.0)));
  };
  EXPECT_EQ(level(320, v), expected(320, v));
  EXPECT_EQ(level(320, v), 150);
  EXPECT_EQ(level(340, v), expected(340, v));  // about one sigma off
  EXPECT_NEAR(level(340, v), 50 + 100 * std::exp(-0.5), 1);
  EXPECT_EQ(level(0, v), 50);
  EXPECT_EQ(level(320, v > 240 ? 0 : 479), 50);
  // Another seed, another row.
  const CameraEffects e2(scenario("", "glare: {intensity: 100, radius_px: 20, period_s: 2}"), 4);
  EXPECT_NE(e2.glare_v(), e.glare_v());
}

}  // namespace
}  // namespace carril::sim
