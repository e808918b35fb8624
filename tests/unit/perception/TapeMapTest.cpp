// TapeMap: tracking a straight line, a circle (curved back-extension), corners; memory update.
#include "firmware/perception/TapeMap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace carril::fw {
namespace {

constexpr double kLookahead = 0.3, kPreview = 1.5;  // [m]

// Camera-like view: points from 0.7 m to 1.8 m along a curve p(s), robot frame, every `step`.
// (`p` must return a Vec2, not an Eigen expression of temporaries.)
template <typename F>
std::vector<Vec2> view(F p, double step = 0.08, double s0 = 0.7, double s1 = 1.8) {
  std::vector<Vec2> v;
  for (double s = s0; s <= s1 + 1e-9; s += step) v.push_back(p(s));
  return v;
}

void add(TapeMap& m, const Pose2& o, const std::vector<Vec2>& pts) {
  m.add(o, pts.data(), pts.size());
}

class TapeMapStraight : public testing::TestWithParam<std::pair<double, double>> {};

TEST_P(TapeMapStraight, LateralAndHeadingOfALineAhead) {
  const auto [c, th] = GetParam();  // line through robot-frame (0, c) at angle th
  const Vec2 u(std::cos(th), std::sin(th));
  for (const Pose2 o : {Pose2{0.0, 0.0, 0.0}, Pose2{1.0, -2.0, 2.5}}) {
    TapeMap m;
    add(m, o, view([&](double s) -> Vec2 { return Vec2(0.0, c) + s * u; }));
    const TrackState t = m.track(o, kLookahead, kPreview);
    ASSERT_TRUE(t.valid);
    // The nearest tape point, robot frame: the foot of the perpendicular from the centre.
    const Vec2 foot = Vec2(0.0, c) - Vec2(0.0, c).dot(u) * u;
    EXPECT_NEAR(t.lateral_m, foot.y(), 1e-6);
    EXPECT_NEAR(std::fabs(t.lateral_m), std::fabs(c) * std::cos(th) * std::cos(th), 1e-6);
    EXPECT_NEAR(t.heading_err_rad, th, 1e-9);
    EXPECT_NEAR(wrap_angle(t.tape_heading_odom - (o.yaw + th)), 0.0, 1e-9);
    EXPECT_NEAR(t.lookahead.x(), (foot + kLookahead * u).x(), 1e-6);
    EXPECT_NEAR(t.lookahead.y(), (foot + kLookahead * u).y(), 1e-6);
    EXPECT_NEAR(t.curvature_ahead, 0.0, 1e-9);
    EXPECT_NEAR(t.corner_turn_rad, 0.0, 1e-9);
    EXPECT_NEAR(t.remaining_m, 1.74 + Vec2(0.0, c).dot(u), 1e-6);  // last point at s = 1.74
  }
}

INSTANTIATE_TEST_SUITE_P(Lines, TapeMapStraight,
                         testing::Values(std::make_pair(0.0, 0.0), std::make_pair(0.2, 0.1),
                                         std::make_pair(-0.15, 0.3), std::make_pair(0.1, -0.25)));

// A circle of radius R (centre to the left for R > 0) tangent to the robot's x axis at its
// centre: robot-frame point at arc length s.
constexpr double kArcStep = 0.07;  // about 16 points over the view, as the detector gives

Vec2 arc(double R, double s) {
  const double a = s / R;
  return {R * std::sin(a), R - R * std::cos(a)};
}

class TapeMapArc : public testing::TestWithParam<double> {};

TEST_P(TapeMapArc, CurvedBackExtensionKeepsARobotOnTheArcOnIt) {
  const double R = GetParam();
  const Pose2 o{0.4, -0.3, 0.6};
  TapeMap m;
  add(m, o, view([&](double s) { return arc(R, s); }, kArcStep));
  const TrackState t = m.track(o, kLookahead, kPreview);
  ASSERT_TRUE(t.valid);
  // What a straight back-extension of the first segment would say: ~ d^2 / (2R).
  const Vec2 a = arc(R, 0.7), b = arc(R, 0.7 + kArcStep), dir = (b - a).normalized();
  const Vec2 foot = a + (Vec2::Zero() - a).dot(dir) * dir;
  const double straight = foot.y();
  EXPECT_GT(std::fabs(straight), 0.7 * 0.7 / (2.0 * std::fabs(R)) * 0.8);
  EXPECT_LT(std::fabs(t.lateral_m), 0.25 * std::fabs(straight));  // the curve helps ...
  EXPECT_LT(std::fabs(t.lateral_m), 0.005) << "straight extension: " << straight;  // ... enough
  EXPECT_LT(std::fabs(t.heading_err_rad), 0.05);
  EXPECT_GT(t.curvature_ahead * R, 0.0);  // curves the right way
  EXPECT_NEAR(t.curvature_ahead, 1.0 / R, 0.15 / std::fabs(R));
}

TEST_P(TapeMapArc, OffsetFromTheArcIsMeasured) {
  const double R = GetParam();
  TapeMap m;
  add(m, Pose2{}, view([&](double s) { return arc(R, s); }, kArcStep));
  for (const double d : {0.1, -0.1}) {  // robot d to the left of the tape where it stands
    const TrackState t = m.track(Pose2{0.0, d, 0.0}, kLookahead, kPreview);
    ASSERT_TRUE(t.valid);
    EXPECT_NEAR(t.lateral_m, -d, 0.005) << "R=" << R << " d=" << d;
  }
}

INSTANTIATE_TEST_SUITE_P(Radius, TapeMapArc, testing::Values(1.5, -1.5, 3.0, -3.0));

TEST(TapeMapTest, NinetyDegreeCornerWithinThePreview) {
  for (const double side : {1.0, -1.0}) {
    std::vector<Vec2> pts;
    for (double x = 0.7; x < 1.2 - 1e-9; x += 0.1) pts.emplace_back(x, 0.0);
    for (double y = 0.0; y <= 0.8 + 1e-9; y += 0.1) pts.emplace_back(1.2, side * y);
    TapeMap m;
    add(m, Pose2{}, pts);
    const TrackState t = m.track(Pose2{}, kLookahead, kPreview);
    ASSERT_TRUE(t.valid);
    EXPECT_NEAR(t.corner_turn_rad, side * kPi / 2, 0.05);
    EXPECT_NEAR(t.corner_dist_m, 1.2, 0.1);
    // Not within a shorter preview.
    const TrackState near = m.track(Pose2{}, kLookahead, 0.9);
    EXPECT_LT(std::fabs(near.corner_turn_rad), 0.1);
  }
}

TEST(TapeMapTest, AddReplacesFromTheNewNearestPointOnAndKeepsWhatIsBehind) {
  TapeMap m;
  add(m, Pose2{}, view([](double s) { return Vec2(s, 0.0); }, 0.1));  // x 0.7 .. 1.8
  ASSERT_EQ(m.size(), 12U);
  // From 0.5 m further on the tape is seen 5 cm further left.
  const Pose2 o{0.5, 0.0, 0.0};
  add(m, o, view([](double s) { return Vec2(s, 0.05); }, 0.1));  // odom x 1.2 .. 2.3
  std::size_t old = 0, fresh = 0;
  for (const Vec2& p : m.points()) {
    if (p.x() < 1.195) {
      EXPECT_NEAR(p.y(), 0.0, 1e-12);
      ++old;
    } else {
      EXPECT_NEAR(p.y(), 0.05, 1e-12) << "stale point at x=" << p.x();
      ++fresh;
    }
  }
  EXPECT_EQ(old, 5U);  // 0.7 .. 1.1, behind the new nearest point
  EXPECT_EQ(fresh, 12U);
  for (std::size_t i = 1; i < m.size(); ++i) {
    EXPECT_GT(m.points()[i].x(), m.points()[i - 1].x());  // path order
  }
}

TEST(TapeMapTest, AddSkipsPointsCloserThanTheMinimumSpacing) {
  TapeMap m;
  std::vector<Vec2> dense;
  for (int i = 0; i < 16; ++i) dense.emplace_back(0.7 + 0.02 * i, 0.0);
  add(m, Pose2{}, dense);
  for (std::size_t i = 1; i < m.size(); ++i) {
    EXPECT_GE((m.points()[i] - m.points()[i - 1]).norm(), 0.06 - 1e-12);
  }
  EXPECT_GE(m.size(), 5U);
}

// Variant 684 of the thesis campaign: a corner's new leg seen only as a strip across the bottom of
// the view. Its row-band centroids bunch, and the frame's last two points zig-zag back across the
// corner; the memory keeps the new leg's direction, not a false right turn at its end.
TEST(TapeMapTest, ARaggedTailOfShortSharpStepsIsDropped) {
  TapeMap m;
  std::vector<Vec2> pts;
  for (int i = 0; i <= 4; ++i) pts.emplace_back(0.7 + 0.07 * i, 0.0);  // the old leg, to x = 0.98
  pts.emplace_back(0.98, 0.22);                                        // the new leg, turning left
  pts.emplace_back(1.04, 0.21);                                        // 6 cm to the right
  pts.emplace_back(1.05, 0.11);  // and back down across the corner
  add(m, Pose2{}, pts);
  ASSERT_GE(m.size(), 3U);
  const Vec2 last = m.points()[m.size() - 1], before = m.points()[m.size() - 2];
  EXPECT_NEAR(last.x(), 0.98, 1e-9);
  EXPECT_NEAR(last.y(), 0.22, 1e-9);
  EXPECT_NEAR(std::atan2(last.y() - before.y(), last.x() - before.x()), kPi / 2, 1e-9);
  // A real corner's new leg, a step of two spacings or more, stays.
  TapeMap corner;
  pts.resize(6);
  pts.emplace_back(0.98, 0.35);
  add(corner, Pose2{}, pts);
  EXPECT_NEAR(corner.points()[corner.size() - 1].y(), 0.35, 1e-9);
  // So do short steps that turn the path once, as a corner does.
  TapeMap once;
  std::vector<Vec2> bend;
  for (int i = 0; i <= 4; ++i) bend.emplace_back(0.7 + 0.07 * i, 0.0);
  bend.emplace_back(0.99, 0.07);
  bend.emplace_back(0.99, 0.15);
  add(once, Pose2{}, bend);
  EXPECT_NEAR(once.points()[once.size() - 1].y(), 0.15, 1e-9);
}

// corners seed 37: past a corner, memory ended with two centroids from frames that saw both legs,
// pointing on along the old leg. Every point of every later frame (the new leg, seen well) turned
// the path back by more than 100 deg from them and was dropped: 0.07 m of tape was left ahead,
// and the robot stood on the new leg, seeing it, until the time ran out. Now 15 frames in a row
// of which no point follows memory drop such a stale end of it (two points at most); fewer are
// usual at a corner and change nothing.
TEST(TapeMapTest, FramesThatCannotFollowMemoryDropItsStaleEnd) {
  TapeMap m;
  std::vector<Vec2> seen;
  for (int i = 0; i <= 4; ++i) seen.emplace_back(0.7 + 0.07 * i, 0.2);  // the old leg
  seen.emplace_back(1.01, 0.0);   // centroids straddling the corner,
  seen.emplace_back(1.07, 0.02);  // the last pointing on east
  add(m, Pose2{}, seen);
  ASSERT_EQ(m.size(), 7U);
  // On the new leg (south along x = 1.07), turned 0.27 rad short of it.
  const Pose2 o{1.01, 0.0, -kPi / 2 + 0.27};
  std::vector<Vec2> leg;
  for (double d = 0.7; d <= 1.8 + 1e-9; d += 0.08) leg.push_back(to_robot(o, Vec2(1.07, -d)));
  for (int f = 1; f < 15; ++f) {
    add(m, o, leg);
    ASSERT_EQ(m.size(), 7U) << "frame " << f;  // memory held: its end still the corner's
    EXPECT_EQ(m.points()[6], Vec2(1.07, 0.02));
  }
  add(m, o, leg);  // the 15th
  EXPECT_LT((m.points()[m.size() - 1] - to_world(o, leg.back())).norm(), 1e-9);
  for (const Vec2& p : m.points()) EXPECT_FALSE(p.x() > 1.06 && p.y() > -0.5) << p.transpose();
  const TrackState t = m.track(o, kLookahead, kPreview);
  ASSERT_TRUE(t.valid);
  EXPECT_GT(t.remaining_m, 1.5);
  // A frame that agrees with memory's end keeps it.
  TapeMap straight;
  add(straight, Pose2{}, view([](double s) { return Vec2(s, 0.0); }, 0.1));
  const std::size_t before = straight.size();
  add(straight, Pose2{1.5, 0.0, 0.0}, view([](double s) { return Vec2(s, 0.0); }, 0.1));
  EXPECT_EQ(straight.size(), 2 * before);
}

TEST(TapeMapTest, CapacityIsRespected) {
  TapeMap m;
  Pose2 o;
  for (int f = 0; f < 400; ++f) {
    o.x += 0.05;
    o.y = 0.3 * std::sin(0.02 * f);
    const auto pts = view([](double s) { return Vec2(s, 0.01); }, 0.07);
    add(m, o, pts);
    ASSERT_LE(m.size(), TapeMap::kMaxPoints);
    // The newest frame is all there, at the end.
    const Vec2 last = to_world(o, pts.back());
    ASSERT_NEAR((m.points()[m.size() - 1] - last).norm(), 0.0, 1e-9);
  }
  EXPECT_GT(m.size(), 100U);
}

TEST(TapeMapTest, RemainingDecreasesAsTheRobotAdvances) {
  TapeMap m;
  add(m, Pose2{}, view([](double s) { return Vec2(s, 0.0); }, 0.1));
  double prev = 1e9;
  for (double x = 0.0; x <= 1.5; x += 0.25) {
    const TrackState t = m.track(Pose2{x, 0.02, 0.0}, kLookahead, kPreview);
    ASSERT_TRUE(t.valid);
    EXPECT_NEAR(t.remaining_m, 1.8 - x, 1e-6);
    EXPECT_LT(t.remaining_m, prev);
    prev = t.remaining_m;
  }
}

TEST(TapeMapTest, FarSegmentIsTheLastStretchOfTape) {
  TapeMap m;
  Vec2 point;
  double heading = 0.0;
  EXPECT_FALSE(m.far_segment(0.3, point, heading));
  std::vector<Vec2> pts;
  for (double x = 0.7; x < 1.2 - 1e-9; x += 0.1) pts.emplace_back(x, 0.0);
  for (double y = 0.0; y <= 0.8 + 1e-9; y += 0.1) pts.emplace_back(1.2, y);
  const Pose2 o{2.0, 1.0, 0.5};
  add(m, o, pts);
  ASSERT_TRUE(m.far_segment(0.3, point, heading));
  const Vec2 last = to_world(o, pts.back());
  EXPECT_NEAR((point - last).norm(), 0.0, 1e-9);
  EXPECT_NEAR(wrap_angle(heading - (o.yaw + kPi / 2)), 0.0, 1e-9);
}

// Just past a corner, with only 0.2 m of the new leg seen, the far segment is that leg's direction,
// not the chord across the corner (which pointed 34 deg off it and started a bypass in that
// frame: thesis campaign variant 219). An arc of 1.2 m radius stays one stretch.
TEST(TapeMapTest, FarSegmentJustPastACornerIsTheNewLeg) {
  TapeMap m;
  std::vector<Vec2> pts;
  for (double x = 0.7; x < 1.2 - 1e-9; x += 0.05) pts.emplace_back(x, 0.0);
  for (double y = 0.0; y <= 0.2 + 1e-9; y += 0.05) pts.emplace_back(1.2, y);
  add(m, Pose2{}, pts);
  Vec2 point;
  double heading = 0.0;
  ASSERT_TRUE(m.far_segment(0.3, point, heading));
  EXPECT_NEAR(wrap_angle(heading - kPi / 2), 0.0, 1e-9);
  EXPECT_NEAR((point - Vec2(1.2, 0.2)).norm(), 0.0, 1e-9);
  TapeMap arc;
  std::vector<Vec2> a;
  for (double t = 0.0; t <= 0.6 + 1e-9; t += 0.02)
    a.emplace_back(1.2 * std::sin(t), 1.2 - 1.2 * std::cos(t));
  add(arc, Pose2{}, a);
  ASSERT_TRUE(arc.far_segment(0.3, point, heading));
  // The chord of the last 0.3 m of the arc (and one point more): its middle's tangent.
  EXPECT_NEAR(heading, 0.6 - 0.15 / 1.2 - 0.01, 0.02);
}

TEST(TapeMapTest, FewerThanTwoPointsIsNotTracked) {
  TapeMap m;
  EXPECT_TRUE(m.empty());
  EXPECT_FALSE(m.track(Pose2{}, kLookahead, kPreview).valid);
  const Vec2 one(0.7, 0.0);
  m.add(Pose2{}, &one, 1);
  EXPECT_FALSE(m.track(Pose2{}, kLookahead, kPreview).valid);
  add(m, Pose2{}, view([](double s) { return Vec2(s, 0.0); }));
  EXPECT_FALSE(m.empty());
  m.clear();
  EXPECT_FALSE(m.track(Pose2{}, kLookahead, kPreview).valid);
}

// Issue 46 item 4: a piece of worn tape too small to be tape on its own continues memory when it
// lies on the remembered path or on its continuation past the end (a 15 cm gap further on, along
// the curve the tape was bending on), running the same way; a piece beside the path, across it,
// past a corner memory cannot predict, or a speck does not.
TEST(TapeMapTest, APieceContinuesTheRememberedTapeOnlyOnItsLine) {
  const Pose2 o{1.0, -2.0, 2.5};
  const auto piece = [&](const Vec2& from, const Vec2& to) {
    std::vector<Vec2> v;
    for (int i = 0; i <= 4; ++i) v.push_back(from + (to - from) * (i / 4.0));
    return v;
  };
  bool extends = true;
  TapeMap straight;
  add(straight, o, view([](double s) { return Vec2(s, 0.0); }));  // memory ends 1.8 m ahead
  // On memory: it continues, but says nothing new.
  std::vector<Vec2> p = piece(Vec2(1.0, 0.01), Vec2(1.12, 0.0));
  EXPECT_TRUE(straight.continues(o, p.data(), p.size(), extends));
  EXPECT_FALSE(extends);
  // After a 15 cm gap past memory's end, and a second gap further on.
  p = piece(Vec2(1.95, 0.0), Vec2(2.07, 0.01));
  EXPECT_TRUE(straight.continues(o, p.data(), p.size(), extends));
  EXPECT_TRUE(extends);
  p = piece(Vec2(2.25, -0.02), Vec2(2.37, -0.02));
  EXPECT_TRUE(straight.continues(o, p.data(), p.size(), extends));
  // Beside the line (10 cm off), across it, past the reach, and a speck on it.
  p = piece(Vec2(1.95, 0.10), Vec2(2.07, 0.10));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));
  p = piece(Vec2(1.95, -0.03), Vec2(1.99, 0.03));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));
  p = piece(Vec2(5.9, 0.0), Vec2(6.02, 0.0));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));
  p = piece(Vec2(1.95, 0.0), Vec2(1.97, 0.0));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));
  // Running backwards along the line.
  p = piece(Vec2(2.07, 0.0), Vec2(1.95, 0.0));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));
  // The new leg of a corner (90 deg left) just past memory's end: not predicted.
  p = piece(Vec2(1.9, 0.05), Vec2(1.9, 0.17));
  EXPECT_FALSE(straight.continues(o, p.data(), p.size(), extends));

  // A circle of radius 1.2 m: a piece past a gap lies on the continued circle; one 8 cm outside
  // it does not.
  const double r = 1.2;
  const auto on_circle = [&](double s) {
    return Vec2(r * std::sin(s / r), r - r * std::cos(s / r));
  };
  TapeMap arc;
  add(arc, o, view(on_circle));
  p = piece(on_circle(1.95), on_circle(2.07));
  EXPECT_TRUE(arc.continues(o, p.data(), p.size(), extends));
  EXPECT_TRUE(extends);
  const Vec2 outward = on_circle(2.01) - Vec2(0.0, r);
  const Vec2 off = outward.normalized() * 0.08;  // 8 cm outside the circle
  p = piece(on_circle(1.95) + off, on_circle(2.07) + off);
  EXPECT_FALSE(arc.continues(o, p.data(), p.size(), extends));

  TapeMap none;  // nothing remembered: no piece continues anything
  p = piece(Vec2(1.0, 0.0), Vec2(1.12, 0.0));
  EXPECT_FALSE(none.continues(o, p.data(), p.size(), extends));
}

}  // namespace
}  // namespace carril::fw
