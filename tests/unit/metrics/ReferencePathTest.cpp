#include "host_sim/metrics/ReferencePath.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::sim {
namespace {

const Rgb kWhite{255, 255, 255}, kBlue{0, 0, 255};

Scenario with_lines(std::vector<LineSpec> lines) {
  Scenario sc;
  sc.mission.line_color = kWhite;
  sc.lines = std::move(lines);
  return sc;
}

LineSpec line(Rgb c, std::vector<Vec2> pts) {
  LineSpec l;
  l.color = c;
  l.points = std::move(pts);
  return l;
}

TEST(ReferencePathTest, LengthOfKnownPolyline) {
  const ReferencePath p(with_lines({line(kWhite, {{0, 0}, {3, 0}, {3, 4}})}));
  ASSERT_FALSE(p.empty());
  EXPECT_NEAR(p.length_m(), 7.0, 1e-12);
  EXPECT_FALSE(p.closed());
}

TEST(ReferencePathTest, DropsConsecutiveDuplicates) {
  const ReferencePath p(with_lines({line(kWhite, {{0, 0}, {0.0005, 0}, {1, 0}, {1, 0}})}));
  EXPECT_EQ(p.points().size(), 2u);
  EXPECT_NEAR(p.length_m(), 1.0, 1e-12);
}

TEST(ReferencePathTest, NearestPointAndDistance) {
  const ReferencePath p(with_lines({line(kWhite, {{0, 0}, {3, 0}, {3, 4}})}));
  PathPoint n = p.nearest({1.0, 0.5});
  EXPECT_NEAR(n.s_m, 1.0, 1e-12);
  EXPECT_NEAR(n.dist_m, 0.5, 1e-12);
  EXPECT_NEAR(n.p.x, 1.0, 1e-12);
  EXPECT_NEAR(n.p.y, 0.0, 1e-12);
  n = p.nearest({4.0, 2.0});
  EXPECT_NEAR(n.s_m, 5.0, 1e-12);
  EXPECT_NEAR(n.dist_m, 1.0, 1e-12);
  n = p.nearest({-1.0, 0.0});  // beyond the start: the end point
  EXPECT_NEAR(n.s_m, 0.0, 1e-12);
  EXPECT_NEAR(n.dist_m, 1.0, 1e-12);
}

TEST(ReferencePathTest, NearestInWindow) {
  // U shape: out along y=0, back along y=1.
  const ReferencePath p(with_lines({line(kWhite, {{0, 0}, {5, 0}, {5, 1}, {0, 1}})}));
  const PathPoint global = p.nearest({2.0, 0.9});
  EXPECT_NEAR(global.s_m, 9.0, 1e-12);
  const PathPoint windowed = p.nearest_in({2.0, 0.9}, 1.0, 4.0);
  EXPECT_NEAR(windowed.s_m, 2.0, 1e-12);
  EXPECT_NEAR(windowed.dist_m, 0.9, 1e-12);
  // A window ahead of the point: its start is the nearest.
  EXPECT_NEAR(p.nearest_in({1.0, 0.0}, 3.0, 4.0).s_m, 3.0, 1e-12);
}

TEST(ReferencePathTest, ClosedDetection) {
  const ReferencePath square(
      with_lines({line(kWhite, {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {0.005, 0.0}})}));
  EXPECT_TRUE(square.closed());
  EXPECT_NEAR(square.length_m(), 8.0, 0.01);
  const ReferencePath ell(with_lines({line(kWhite, {{0, 0}, {2, 0}, {2, 2}})}));
  EXPECT_FALSE(ell.closed());
}

TEST(ReferencePathTest, AtWrapsOnClosedAndClampsOnOpen) {
  const ReferencePath square(with_lines({line(kWhite, {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}})}));
  ASSERT_TRUE(square.closed());
  Vec2 a = square.at(9.0);  // one lap + 1 m
  EXPECT_NEAR(a.x, 1.0, 1e-12);
  EXPECT_NEAR(a.y, 0.0, 1e-12);
  a = square.at(-1.0);  // 1 m before the seam: on the last side
  EXPECT_NEAR(a.x, 0.0, 1e-12);
  EXPECT_NEAR(a.y, 1.0, 1e-12);
  a = square.at(3.0);
  EXPECT_NEAR(a.x, 2.0, 1e-12);
  EXPECT_NEAR(a.y, 1.0, 1e-12);
  // A window across the seam finds points on both sides of it.
  EXPECT_NEAR(square.nearest_in({0.5, -0.1}, 7.0, 9.0).s_m, 0.5, 1e-12);
  EXPECT_NEAR(square.nearest_in({-0.1, 0.5}, 7.0, 9.0).s_m, 7.5, 1e-12);

  const ReferencePath ell(with_lines({line(kWhite, {{0, 0}, {2, 0}, {2, 2}})}));
  a = ell.at(10.0);
  EXPECT_NEAR(a.x, 2.0, 1e-12);
  EXPECT_NEAR(a.y, 2.0, 1e-12);
  a = ell.at(-3.0);
  EXPECT_NEAR(a.x, 0.0, 1e-12);
  EXPECT_NEAR(a.y, 0.0, 1e-12);
}

TEST(ReferencePathTest, FiltersByColourAndConcatenatesInFileOrder) {
  const ReferencePath p(with_lines({line(kWhite, {{0, 0}, {1, 0}}), line(kBlue, {{0, 5}, {9, 5}}),
                                    line(kWhite, {{1, 0}, {1, 2}})}));
  ASSERT_EQ(p.points().size(), 3u);  // the shared point (1,0) appears once
  EXPECT_NEAR(p.length_m(), 3.0, 1e-12);
  EXPECT_NEAR(p.points()[2].y, 2.0, 1e-12);
  EXPECT_NEAR(p.nearest({1.0, 1.5}).s_m, 2.5, 1e-12);
  // Nothing near the blue line belongs to the path.
  EXPECT_NEAR(p.nearest({5.0, 5.0}).dist_m, std::hypot(4.0, 3.0), 1e-12);

  Scenario blue = with_lines({line(kWhite, {{0, 0}, {1, 0}}), line(kBlue, {{0, 5}, {9, 5}})});
  blue.mission.line_color = kBlue;
  const ReferencePath b(blue);
  EXPECT_NEAR(b.length_m(), 9.0, 1e-12);
}

TEST(ReferencePathTest, EmptyWithoutMissionColour) {
  const ReferencePath p(with_lines({line(kBlue, {{0, 0}, {1, 0}})}));
  EXPECT_TRUE(p.empty());
  EXPECT_EQ(p.length_m(), 0.0);
  EXPECT_EQ(p.nearest({1, 1}).dist_m, 0.0);
}

}  // namespace
}  // namespace carril::sim
