// Worn tape: the pieces left between gaps add up to the line less its gaps; gaps come from the
// seed (the same for the same seed, another for another) at the rate asked; the fade mixes toward
// the floor; a camera over a gap sees no tape where it saw tape before.
#include "host_sim/sensors/TapeWear.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hal/Types.hpp"
#include "host_sim/sensors/CameraRenderer.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

double length_of(const std::vector<Vec2>& pts) {
  double len = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    len += std::hypot(pts[i + 1].x - pts[i].x, pts[i + 1].y - pts[i].y);
  }
  return len;
}

TEST(TapeWearTest, PiecesAreTheLineLessItsGaps) {
  const std::vector<Vec2> line = {{0, 0}, {4, 0}, {4, 3}};  // 7 m with a corner at 4 m
  const auto whole = tape_pieces(line, {});
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_NEAR(length_of(whole[0]), 7.0, 1e-12);
  // Gaps across the corner and inside the second leg, overlapping ones merged by the walk.
  const auto pieces = tape_pieces(line, {{3.5, 4.5}, {5.0, 5.5}, {5.25, 6.0}});
  ASSERT_EQ(pieces.size(), 3u);
  EXPECT_NEAR(length_of(pieces[0]), 3.5, 1e-12);
  EXPECT_NEAR(length_of(pieces[1]), 0.5, 1e-12);
  EXPECT_NEAR(length_of(pieces[2]), 1.0, 1e-12);
  EXPECT_NEAR(pieces[1].front().x, 4.0, 1e-12);
  EXPECT_NEAR(pieces[1].front().y, 0.5, 1e-12);
  EXPECT_NEAR(pieces[2].back().y, 3.0, 1e-12);
  // A gap over the whole line leaves nothing.
  EXPECT_TRUE(tape_pieces(line, {{-1.0, 8.0}}).empty());
}

Scenario straight_tape(double gaps_per_m, double fade) {
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml, R"(
name: worn
duration_s: 1
floor: {color: [90, 90, 90]}
robot: {preset: campero}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-0.5, 0], [100, 0]]}]
tape_wear: {gaps_per_m: %g, gap_length_m: 0.2, fade: %g}
)",
                gaps_per_m, fade);
  return test::load_text(yaml);
}

TEST(TapeWearTest, GapsComeFromTheSeedAtTheRateAsked) {
  const Scenario s = straight_tape(0.5, 0.0);
  const auto a = tape_gaps(s, 1), b = tape_gaps(s, 1), c = tape_gaps(s, 2);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(a[0].size(), b[0].size());
  for (std::size_t i = 0; i < a[0].size(); ++i) EXPECT_EQ(a[0][i].from_m, b[0][i].from_m);
  EXPECT_NE(a[0].front().from_m, c[0].front().from_m);
  // 100.5 m at 0.5 per metre: 50.25 on average; over 200 seeds the mean is within 0.2.
  double sum = 0.0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const auto g = tape_gaps(s, seed);
    sum += double(g[0].size());
    for (const TapeGap& gap : g[0]) {
      EXPECT_GE(gap.from_m, 0.0);
      EXPECT_LE(gap.from_m, 100.5);
      EXPECT_NEAR(gap.to_m - gap.from_m, 0.2, 1e-12);
    }
  }
  EXPECT_NEAR(sum / 200.0, 50.25, 0.2);
  EXPECT_TRUE(tape_gaps(straight_tape(0.0, 0.0), 1)[0].empty());
}

TEST(TapeWearTest, AFadedTapeMixesTowardTheFloor) {
  const Rgb white{255, 255, 255}, floor{90, 90, 90};
  EXPECT_EQ(faded(white, floor, 0.0), white);
  EXPECT_EQ(faded(white, floor, 1.0), floor);
  EXPECT_EQ(faded(white, floor, 0.5), (Rgb{173, 173, 173}));
}

// Pixels brighter than `level` in every channel.
int bright_pixels(const hal::CameraFrame& f, int level) {
  int n = 0;
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const std::uint8_t* p = f.pixel(x, y);
      if (p[0] > level && p[1] > level && p[2] > level) ++n;
    }
  }
  return n;
}

TEST(TapeWearTest, TheCameraSeesTheGapsAndTheFade) {
  auto frame = std::make_unique<hal::CameraFrame>();
  const Pose2 at{0.0, 0.0, 0.0};
  // Whole tape: many white pixels; faded half way: none as bright as white, some at its level.
  Scenario whole = straight_tape(0.0, 0.0);
  CameraRenderer(whole, 1).render(at, *frame);
  const int white = bright_pixels(*frame, 240);
  EXPECT_GT(white, 500);
  Scenario fade = straight_tape(0.0, 0.5);
  CameraRenderer(fade, 1).render(at, *frame);
  EXPECT_EQ(bright_pixels(*frame, 240), 0);
  EXPECT_GT(bright_pixels(*frame, 160), white / 2);
  // Heavy wear: over 100 seeds, less tape in view on average, and some views with none.
  Scenario worn = straight_tape(4.0, 0.0);
  int less = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    CameraRenderer(worn, seed).render(at, *frame);
    if (bright_pixels(*frame, 240) < white * 9 / 10) ++less;
  }
  EXPECT_GE(less, 15);
}

}  // namespace
}  // namespace carril::sim
