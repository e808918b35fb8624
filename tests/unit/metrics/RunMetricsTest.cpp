#include "host_sim/metrics/RunMetrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace carril::sim {
namespace {

const Rgb kWhite{255, 255, 255}, kYellow{255, 255, 0}, kBlue{0, 0, 255};

Scenario with_path(std::vector<Vec2> pts) {
  Scenario sc;
  sc.mission.line_color = kWhite;
  sc.mission.end_color = kYellow;
  LineSpec l;
  l.color = kWhite;
  l.points = std::move(pts);
  sc.lines.push_back(std::move(l));
  return sc;
}

TickSample at(double t, double x, double y, bool following = true) {
  TickSample s;
  s.t_s = t;
  s.pose = {x, y, 0.0};
  s.vx_mps = 0.5;
  s.following = following;
  return s;
}

// Drives straight from a to b in steps of about `step` metres, one tick per step at `dt`.
void drive(RunMetrics& m, double& t, Vec2 a, Vec2 b, double step = 0.01, double dt = 0.02) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  for (int i = 1; i <= n; ++i) {
    const double f = static_cast<double>(i) / n;
    t += dt;
    m.add(at(t, a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)));
  }
}

TEST(RunMetricsTest, StraightOpenTapeFullProgressNoCrossTrack) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {10, 0});
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
  EXPECT_EQ(m.laps(), 0);
  EXPECT_NEAR(m.cross_track_rms_m(), 0.0, 1e-12);
  EXPECT_NEAR(m.cross_track_max_m(), 0.0, 1e-12);
}

// Issue 46 item 8: progress is distance driven along the route. A robot that never moves (at
// the open tape's end, 3 cm short of it, or on a loop) scores 0, not a finished run.
TEST(RunMetricsTest, ARobotThatNeverMovesScoresNoProgress) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  for (const double x : {10.0, 9.97, 5.0}) {
    RunMetrics m(sc);
    for (int i = 0; i < 500; ++i) m.add(at(0.02 * i, x, 0.0));
    EXPECT_DOUBLE_EQ(m.progress(), 0.0) << "standing at x = " << x;
  }
  const Scenario loop = with_path({{0, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 0}});
  RunMetrics m(loop);
  for (int i = 0; i < 500; ++i) m.add(at(0.02 * i, 2.0, 0.0));
  EXPECT_DOUBLE_EQ(m.progress(), 0.0);
  EXPECT_EQ(m.laps(), 0);
}

TEST(RunMetricsTest, HalfWayIsHalfProgress) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {5, 0});
  EXPECT_NEAR(m.progress(), 0.5, 1e-9);
}

TEST(RunMetricsTest, OffsetGivesRmsOfOffset) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0.02));
  drive(m, t, {0, 0.02}, {10, 0.02});
  EXPECT_NEAR(m.cross_track_rms_m(), 0.02, 1e-9);
  EXPECT_NEAR(m.cross_track_max_m(), 0.02, 1e-9);
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
}

TEST(RunMetricsTest, RmsAndMaxIgnoreNonFollowingTicks) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  EXPECT_NEAR(m.add(at(0.0, 1, 0.1, true)), 0.1, 1e-12);
  EXPECT_NEAR(m.add(at(0.1, 2, 0.5, false)), 0.5, 1e-12);  // returned, but not scored
  EXPECT_NEAR(m.add(at(0.2, 3, -0.1, true)), 0.1, 1e-12);
  EXPECT_NEAR(m.cross_track_rms_m(), 0.1, 1e-12);
  EXPECT_NEAR(m.cross_track_max_m(), 0.1, 1e-12);

  RunMetrics none(sc);
  none.add(at(0.0, 1, 0.3, false));
  EXPECT_EQ(none.cross_track_rms_m(), 0.0);
  EXPECT_EQ(none.cross_track_max_m(), 0.0);
}

TEST(RunMetricsTest, DetourThatRejoinsIsCredited) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {4, 0});
  drive(m, t, {4, 0}, {4, 1});  // leave the tape by 1 m
  drive(m, t, {4, 1}, {6, 1});  // for a 2 m stretch
  EXPECT_LT(m.progress(), 0.45);
  drive(m, t, {6, 1}, {6, 0});  // rejoin
  drive(m, t, {6, 0}, {10, 0});
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
}

TEST(RunMetricsTest, ALongBypassIsCredited) {
  // Round two obstacles: off the tape at 3 m, 1.2 m to the side for 5.5 m, back at 8.5 m (more
  // than kWindowM ahead, but the robot drove further than it skipped).
  const Scenario sc = with_path({{0, 0}, {20, 0}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {3, 0});
  drive(m, t, {3, 0}, {3, 1.2});
  drive(m, t, {3, 1.2}, {8.5, 1.2});
  drive(m, t, {8.5, 1.2}, {8.5, 0});
  EXPECT_NEAR(m.progress(), 8.5 / 20.0, 0.01);
  drive(m, t, {8.5, 0}, {20, 0});
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
}

TEST(RunMetricsTest, ShortcutAcrossUIsNotCredited) {
  // Out along y=0 to x=5, across, back along y=2: 12 m.
  const Scenario sc = with_path({{0, 0}, {5, 0}, {5, 2}, {0, 2}});
  RunMetrics m(sc);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {2, 0});
  drive(m, t, {2, 0}, {2, 2});  // straight across to the return leg
  drive(m, t, {2, 2}, {0, 2});  // and along it to the end
  EXPECT_NEAR(m.progress(), 2.0 / 12.0, 0.01);
  EXPECT_EQ(m.laps(), 0);
}

TEST(RunMetricsTest, OneAndAHalfLapsOfACircle) {
  // Points like the loader's discretised arc: radius 3, no more than 2 cm apart, closed.
  const double r = 3.0, two_pi = 2.0 * std::numbers::pi;
  const int n = static_cast<int>(std::ceil(two_pi * r / 0.02));
  std::vector<Vec2> pts;
  for (int i = 0; i <= n; ++i) {
    const double a = two_pi * i / n;
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  const Scenario sc = with_path(pts);
  RunMetrics m(sc);
  ASSERT_TRUE(m.path().closed());
  EXPECT_EQ(m.progress(), 0.0);  // nothing yet
  const int steps = 3 * n;       // 1.5 laps at half the point spacing
  for (int i = 0; i <= steps; ++i) {
    const double a = two_pi * 1.5 * i / steps;
    m.add(at(0.01 * i, r * std::cos(a), r * std::sin(a)));
    if (i == steps / 2) {
      EXPECT_EQ(m.laps(), 0);
      EXPECT_NEAR(m.progress(), 0.75, 0.01);
    }
  }
  EXPECT_EQ(m.laps(), 1);
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
  EXPECT_NEAR(m.cross_track_max_m(), 0.0, 1e-4);
}

class RunMetricsEndTest : public testing::Test {
 protected:
  RunMetricsEndTest() : sc_(with_path({{0, 0}, {5, 0}})) {
    MarkSpec end;
    end.color = kYellow;
    end.center = {5.0, 0.0};
    sc_.marks.push_back(end);
    MarkSpec other;
    other.color = kBlue;
    other.center = {2.0, 0.0};
    sc_.marks.push_back(other);
  }
  static TickSample stopped(double x, bool in_end = true) {
    TickSample s = at(10.0, x, 0.0, false);
    s.vx_mps = 0.0;
    s.in_end_state = in_end;
    return s;
  }
  Scenario sc_;
};

TEST_F(RunMetricsEndTest, StoppedInEndNearYellowMark) {
  RunMetrics m(sc_);
  EXPECT_FALSE(m.end_reached());
  EXPECT_FALSE(m.end_stop_error_m().has_value());
  m.add(stopped(4.98));
  ASSERT_TRUE(m.end_reached());
  EXPECT_NEAR(*m.end_stop_error_m(), 0.02, 1e-9);
}

TEST_F(RunMetricsEndTest, NotWhileMoving) {
  RunMetrics m(sc_);
  TickSample s = stopped(4.98);
  s.vy_mps = 0.05;
  m.add(s);
  s = stopped(4.98);
  s.wz_radps = 0.1;
  m.add(s);
  EXPECT_FALSE(m.end_reached());
}

TEST_F(RunMetricsEndTest, NotOutsideEndState) {
  RunMetrics m(sc_);
  m.add(stopped(4.98, false));
  EXPECT_FALSE(m.end_reached());
}

TEST_F(RunMetricsEndTest, NotOnAMarkOfAnotherColourOrTooFar) {
  RunMetrics m(sc_);
  m.add(stopped(2.0));  // on the blue mark
  m.add(stopped(4.7));  // 0.3 m short of the yellow one
  EXPECT_FALSE(m.end_reached());
}

TEST_F(RunMetricsEndTest, StopOnEndMarkShortOfTapeEndCountsAsComplete) {
  sc_.marks[0].center = {4.8, 0.0};
  RunMetrics m(sc_);
  double t = 0.0;
  m.add(at(t, 0, 0));
  drive(m, t, {0, 0}, {4.8, 0});
  EXPECT_LT(m.progress(), 1.0);
  m.add(stopped(4.8));
  EXPECT_TRUE(m.end_reached());
  EXPECT_DOUBLE_EQ(m.progress(), 1.0);
}

TEST(RunMetricsTest, PathLengthAndMeanSpeed) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  m.add(at(1.0, 0, 0));
  m.add(at(2.0, 3, 4));          // 5 m
  TickSample s = at(3.0, 3, 5);  // 1 m
  s.wz_radps = -0.7;
  m.add(s);
  EXPECT_NEAR(m.path_length_m(), 6.0, 1e-12);
  EXPECT_NEAR(m.mean_speed_mps(), 3.0, 1e-12);
  EXPECT_NEAR(m.max_abs_wz_radps(), 0.7, 1e-12);

  RunMetrics single(sc);
  single.add(at(1.0, 0, 0));
  EXPECT_EQ(single.mean_speed_mps(), 0.0);
}

TEST(RunMetricsTest, CollisionsCount) {
  const Scenario sc = with_path({{0, 0}, {10, 0}});
  RunMetrics m(sc);
  EXPECT_EQ(m.collisions(), 0);
  m.add_collision();
  m.add_collision();
  EXPECT_EQ(m.collisions(), 2);
}

TEST(RunMetricsTest, NoMissionColourLineMeansEmptyPath) {
  Scenario sc = with_path({{0, 0}, {10, 0}});
  sc.lines[0].color = kBlue;
  RunMetrics m(sc);
  EXPECT_EQ(m.add(at(0.0, 1, 1)), 0.0);
  m.add(at(1.0, 5, 1));
  EXPECT_EQ(m.cross_track_rms_m(), 0.0);
  EXPECT_EQ(m.progress(), 0.0);
  EXPECT_EQ(m.laps(), 0);
  EXPECT_NEAR(m.path_length_m(), 4.0, 1e-12);
}

}  // namespace
}  // namespace carril::sim
