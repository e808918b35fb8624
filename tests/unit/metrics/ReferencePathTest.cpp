#include "host_sim/metrics/ReferencePath.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

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

// nearest() as it was before squared distances screened the segments: hypot for every one.
PathPoint nearest_by_hypot(const ReferencePath& path, Vec2 q) {
  const std::vector<Vec2>& pts = path.points();
  PathPoint best{0.0, std::hypot(q.x - pts.front().x, q.y - pts.front().y), pts.front()};
  double cum = 0.0;  // arc length at point i, summed as the path sums it
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec2 a = pts[i], b = pts[i + 1];
    const double next = cum + std::hypot(b.x - a.x, b.y - a.y), seg = next - cum;
    if (seg > 0.0) {
      const double dx = b.x - a.x, dy = b.y - a.y;
      const double t = std::clamp(((q.x - a.x) * dx + (q.y - a.y) * dy) / (seg * seg), 0.0, 1.0);
      const Vec2 p{a.x + t * dx, a.y + t * dy};
      const double d = std::hypot(q.x - p.x, q.y - p.y);
      if (d < best.dist_m) best = PathPoint{cum + t * seg, d, p};
    }
    cum = next;
  }
  if (path.closed() && best.s_m >= path.length_m()) best.s_m -= path.length_m();
  return best;
}

// nearest_in() as it was before the screen: hypot for every segment in the window.
PathPoint nearest_in_by_hypot(const ReferencePath& path, Vec2 q, double s_from, double s_to) {
  const std::vector<Vec2>& pts = path.points();
  std::vector<double> cum = {0.0};
  for (std::size_t i = 1; i < pts.size(); ++i)
    cum.push_back(cum.back() + std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y));
  const double len = path.length_m();
  PathPoint best;
  bool found = false;
  const auto search = [&](double a, double b) {
    std::size_t i = std::size_t(std::lower_bound(cum.begin(), cum.end(), a) - cum.begin());
    if (i > 0) --i;
    for (; i + 1 < pts.size() && cum[i] <= b; ++i) {
      const double seg = cum[i + 1] - cum[i];
      if (!(seg > 0.0)) continue;
      const double dx = pts[i + 1].x - pts[i].x, dy = pts[i + 1].y - pts[i].y;
      const double t_lo = std::clamp((a - cum[i]) / seg, 0.0, 1.0);
      const double t_hi = std::clamp((b - cum[i]) / seg, 0.0, 1.0);
      if (t_lo > t_hi) continue;
      const double t =
          std::clamp(((q.x - pts[i].x) * dx + (q.y - pts[i].y) * dy) / (seg * seg), t_lo, t_hi);
      const Vec2 p{pts[i].x + t * dx, pts[i].y + t * dy};
      const double d = std::hypot(q.x - p.x, q.y - p.y);
      if (!found || d < best.dist_m) {
        best = PathPoint{cum[i] + t * seg, d, p};
        found = true;
      }
    }
  };
  if (path.closed()) {
    const double span = std::clamp(s_to - s_from, 0.0, len);
    double a = std::fmod(s_from, len);
    if (a < 0.0) a += len;
    if (a + span <= len) {
      search(a, a + span);
    } else {
      search(a, len);
      search(0.0, a + span - len);
    }
    if (found && best.s_m >= len) best.s_m -= len;
  } else {
    const double a = std::clamp(s_from, 0.0, len);
    search(a, std::clamp(s_to, a, len));
  }
  return best;  // the tests' windows always hold a segment
}

// The screening changes nothing, ties included: circles of many short segments queried at their
// centre (every segment about as far), on the path, near it and far off, and random zigzags;
// nearest() over the whole path and nearest_in() over windows up to 3 m long (wrapping round
// the closed circles).
TEST(ReferencePathTest, NearestEqualsTakingHypotOfEverySegmentToTheBit) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int queries = 0;
  for (int shape = 0; shape < 40; ++shape) {
    std::vector<Vec2> pts;
    const double cx = 10.0 * u(rng), cy = 10.0 * u(rng), r = 0.5 + 4.0 * std::abs(u(rng));
    if (shape % 2 == 0) {
      const int n = 8 + shape * 9;  // 8 to 350 segments round a circle, closed
      for (int k = 0; k <= n; ++k) {
        const double a = 2.0 * M_PI * k / n;
        pts.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
      }
      pts.back() = pts.front();
    } else {
      for (int k = 0; k < 4 + shape; ++k) pts.push_back({cx + k * 0.3, cy + r * u(rng)});
    }
    const ReferencePath path(with_lines({line(kWhite, pts)}));
    ASSERT_FALSE(path.empty());
    std::vector<Vec2> qs = {{cx, cy}, pts[1], {pts[1].x + 1e-9, pts[1].y}};
    for (int k = 0; k < 200; ++k) {
      const double spread = k < 100 ? 0.05 : 20.0;
      const Vec2 p = pts[std::size_t(k) % pts.size()];
      qs.push_back({p.x + spread * u(rng), p.y + spread * u(rng)});
    }
    std::uniform_real_distribution<double> along(0.0, path.length_m());
    for (const Vec2& q : qs) {
      const double s_from = along(rng), s_to = s_from + 3.0 * std::abs(u(rng));
      const PathPoint wa = path.nearest_in(q, s_from, s_to);
      const PathPoint wb = nearest_in_by_hypot(path, q, s_from, s_to);
      ASSERT_EQ(wa.dist_m, wb.dist_m) << "shape " << shape << " window " << s_from << " " << s_to;
      ASSERT_EQ(wa.s_m, wb.s_m) << "shape " << shape << " window " << s_from << " " << s_to;
      const PathPoint a = path.nearest(q), b = nearest_by_hypot(path, q);
      ASSERT_EQ(a.dist_m, b.dist_m) << "shape " << shape << " query " << q.x << " " << q.y;
      ASSERT_EQ(a.s_m, b.s_m) << "shape " << shape << " query " << q.x << " " << q.y;
      ASSERT_EQ(a.p.x, b.p.x);
      ASSERT_EQ(a.p.y, b.p.y);
      ++queries;
    }
  }
  EXPECT_EQ(queries, 40 * 203);
}

// A point as far from three segments, to the bit (a square's sides, exact in binary), is the
// earliest one's, whichever segment the query before it was nearest to (nearest() tries that one
// first).
TEST(ReferencePathTest, ATieGoesToTheEarliestSegmentWhateverWasAskedBefore) {
  const ReferencePath p(with_lines({line(kWhite, {{-1, 1}, {-1, -1}, {1, -1}, {1, 1}})}));
  for (const Vec2 before : {Vec2{-1.2, 0.3}, Vec2{0.3, -1.2}, Vec2{1.2, 0.3}, Vec2{0, 0}}) {
    (void)p.nearest(before);
    const PathPoint n = p.nearest({0.0, 0.0});
    EXPECT_EQ(n.dist_m, 1.0);
    EXPECT_EQ(n.s_m, 1.0) << "after " << before.x << " " << before.y;
    EXPECT_EQ(n.p.x, -1.0);
    EXPECT_EQ(n.p.y, 0.0);
  }
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
