// LineBehavior, driven tick by tick: FOLLOW (to END and SEARCH; the pid grace turn) and
// SEARCH (left, right, back, LineNotFound; reacquiring the tape in each phase).
#include "firmware/behavior/LineBehavior.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/behavior/BehaviorBuilders.hpp"

namespace carril::fw {
namespace {

using test::expect_still;
using test::kDt;
using test::Phases;
using test::Sim;
using test::StraightTape;

// ---------------------------------------------------------------------------------------------
// FOLLOW

TEST(LineBehaviorFollowTest, CommandsTheLineController) {
  Sim s(true);
  s.tape.p0 = Vec2(0.0, 0.05);
  s.start_on_tape();
  LineController ref(s.scfg, true);
  for (int i = 0; i < 20; ++i) {
    const TrackState t = s.tape.track(s.pose, s.scfg.marks_lookahead_m);
    const Twist want = ref.follow(t, kDt);
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Follow);
    EXPECT_DOUBLE_EQ(s.out.twist.vx, want.vx);
    EXPECT_DOUBLE_EQ(s.out.twist.vy, want.vy);
    EXPECT_DOUBLE_EQ(s.out.twist.wz, want.wz);
  }
  EXPECT_GT(s.pose.x, 0.05);
}

TEST(LineBehaviorFollowTest, KeepsGoingOnMemoryWhenTheViewIsEmpty) {
  Sim s(false);
  s.start_on_tape();
  s.tape_in_view = false;  // the map still holds tape ahead
  for (int i = 0; i < 50; ++i) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Follow);
    EXPECT_GT(s.out.twist.vx, 0.0);
  }
}

TEST(LineBehaviorFollowTest, ToEndWhenTheMarkIsClose) {
  Sim s(false);
  s.end_known = true;
  s.end_odom = Vec2(2.0, 0.0);
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::End, 1000));
  const double d = (s.end_odom - Vec2(s.last_in.odom.x, s.last_in.odom.y)).norm();
  EXPECT_LT(d, s.cfg.end_approach_m);
  EXPECT_GT(d, s.cfg.end_approach_m - 0.01);
  EXPECT_STREQ(s.mb.phase(), "approach");
  EXPECT_GT(s.out.twist.vx, 0.0);  // the first END tick already drives toward the mark
}

TEST(LineBehaviorFollowTest, IgnoresAnUnknownEndMark) {
  Sim s(false);
  s.end_odom = Vec2(1.0, 0.0);  // end_known false: a stale position must not count
  s.start_on_tape();
  for (int i = 0; i < 400; ++i) s.step();
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_GT(s.pose.x, 1.0);
}

// Memory exhausted (map empty) and lost_frames fresh frames without tape: SEARCH.
TEST(LineBehaviorFollowTest, ToSearchAfterLostFrames) {
  Sim s(false);
  s.start_on_tape();
  s.frame_every = 2;
  for (int i = 0; i < 8; ++i) s.step();
  ASSERT_EQ(s.ticks % 2, 0);
  s.tape_in_view = false;
  s.tape_in_map = false;
  // Fresh frames now on every even tick: the third one (the fifth tick) starts the search.
  for (int i = 0; i < 4; ++i) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Follow) << "tick " << i;
    EXPECT_FALSE(s.out.clear_map);
    EXPECT_EQ(s.mb.line_lost_events(), 0U);
  }
  s.step();
  EXPECT_EQ(s.mb.state(), LineState::Search);
  EXPECT_STREQ(s.mb.phase(), "left");
  EXPECT_TRUE(s.out.clear_map);
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
  EXPECT_EQ(s.mb.line_reacquired_events(), 0U);
}

TEST(LineBehaviorFollowTest, ToSearchAtTheEndOfRememberedTape) {
  Sim s(false);
  s.tape.end_s = 2.0;
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::Search, 3000));
  const double remaining = s.tape.end_s - s.tape.along(s.last_in.odom);
  EXPECT_LT(remaining, 0.05 + 1e-9);
  EXPECT_GT(remaining, 0.0);
  EXPECT_TRUE(s.out.clear_map);
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
  EXPECT_EQ(s.phases, Phases({"find", "track", "left"}));
}

// pid: first turns toward the side of the last error for pid_lost_grace_s, then searches.
class LineBehaviorPidLost : public testing::TestWithParam<double> {};

TEST_P(LineBehaviorPidLost, GraceTurnTowardTheLastError) {
  const double side = GetParam();
  Sim s(false, Strategy::Pid);
  s.tape.p0 = Vec2(0.0, 0.1 * side);
  s.start_on_tape();
  for (int i = 0; i < 5; ++i) s.step();
  ASSERT_EQ(s.mb.state(), LineState::Follow);
  LineController ref(s.scfg, false);
  TrackState t;
  t.valid = true;
  t.remaining_m = 5.0;
  t.lookahead = Vec2(0.3, 0.1 * side);
  ref.follow(t, kDt);
  const Twist lost = ref.lost(kDt);
  ASSERT_GT(lost.wz * side, 0.0);

  s.tape_in_view = false;
  s.tape_in_map = false;
  s.step();
  s.step();
  ASSERT_EQ(s.mb.state(), LineState::Follow);
  s.step();  // third frame without tape: the grace period starts
  const double t0 = s.last_in.t_s;
  int grace_ticks = 0;
  while (s.mb.state() == LineState::Follow && grace_ticks < 500) {
    EXPECT_DOUBLE_EQ(s.out.twist.vx, lost.vx);
    EXPECT_DOUBLE_EQ(s.out.twist.wz, lost.wz);
    EXPECT_GT(s.out.twist.wz * side, 0.0);
    ++grace_ticks;
    s.step();
  }
  EXPECT_EQ(s.mb.state(), LineState::Search);
  EXPECT_NEAR(s.last_in.t_s - t0, s.cfg.pid_lost_grace_s, 0.015);
  EXPECT_TRUE(s.out.clear_map);
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
}

INSTANTIATE_TEST_SUITE_P(Side, LineBehaviorPidLost, testing::Values(1.0, -1.0),
                         [](const auto& i) { return i.param > 0 ? "Left" : "Right"; });

// ---------------------------------------------------------------------------------------------
// SEARCH

// Starts a search with the robot heading `yaw` (no tape anywhere).
void lose_tape(Sim& s, double yaw) {
  s.pose.yaw = yaw;
  s.tape.h = yaw;
  s.start_on_tape();
  ASSERT_EQ(s.mb.state(), LineState::Follow);
  s.tape_in_view = false;
  s.tape_in_map = false;
  ASSERT_TRUE(s.run_until_state(LineState::Search, 3));
}

class LineBehaviorSearch : public testing::TestWithParam<double> {};

TEST_P(LineBehaviorSearch, LeftRightBackThenLineNotFound) {
  Sim s(false);
  lose_tape(s, GetParam());
  const double origin = s.last_in.odom.yaw;
  const double tol = s.cfg.align_tolerance_rad;
  auto rel = [&] { return wrap_angle(s.last_in.odom.yaw - origin); };
  const double w = s.cfg.search_yaw_rate_radps;

  ASSERT_TRUE(s.run_until(
      [&] {
        if (std::string(s.mb.phase()) == "left") {
          EXPECT_DOUBLE_EQ(s.out.twist.wz, w);
          EXPECT_EQ(s.out.twist.vx, 0.0);
        }
        return std::string(s.mb.phase()) == "right";
      },
      1000));
  EXPECT_NEAR(rel(), kPi / 2 - tol, w * kDt + 1e-9);
  EXPECT_DOUBLE_EQ(s.out.twist.wz, -w);

  ASSERT_TRUE(s.run_until(
      [&] {
        if (std::string(s.mb.phase()) == "right") EXPECT_DOUBLE_EQ(s.out.twist.wz, -w);
        return std::string(s.mb.phase()) == "back";
      },
      2000));
  EXPECT_NEAR(rel(), -kPi / 2 + tol, w * kDt + 1e-9);

  ASSERT_TRUE(s.run_until_state(LineState::Fault, 1000));
  EXPECT_LT(std::fabs(wrap_angle(rel() - kPi)), tol);
  EXPECT_STREQ(s.mb.phase(), "stopped");
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], Fault::LineNotFound);
  EXPECT_EQ(s.phases, Phases({"find", "track", "left", "right", "back", "stopped"}));
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
  EXPECT_EQ(s.mb.line_reacquired_events(), 0U);
  EXPECT_DOUBLE_EQ(s.pose.x, s.last_in.odom.x);  // turned on the spot
}

INSTANTIATE_TEST_SUITE_P(Origin, LineBehaviorSearch, testing::Values(0.0, 0.3, 3.0, -2.8));

class LineBehaviorReacquire : public testing::TestWithParam<const char*> {};

TEST_P(LineBehaviorReacquire, FreshFrameWithTapeReturnsToFollow) {
  const std::string phase = GetParam();
  Sim s(true);
  lose_tape(s, 0.2);
  ASSERT_TRUE(s.run_until_phase(phase, 3000));
  for (int i = 0; i < 20; ++i) s.step();
  ASSERT_EQ(std::string(s.mb.phase()), phase);
  // A frame that is not fresh does not count, even if it claims tape.
  s.script = [](BehaviorInput& in) {
    in.fresh_frame = false;
    in.line_visible = true;
  };
  s.step();
  ASSERT_EQ(s.mb.state(), LineState::Search);
  s.script = nullptr;
  s.tape_in_view = true;
  s.step();
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_STREQ(s.mb.phase(), "track");
  EXPECT_EQ(s.mb.line_reacquired_events(), 1U);
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
  EXPECT_EQ(s.phases.back(), "track");
}

INSTANTIATE_TEST_SUITE_P(Phase, LineBehaviorReacquire, testing::Values("left", "right", "back"),
                         [](const auto& i) { return std::string(i.param); });

// The tape lost along +x from the origin, remembered in path order (direction `dir` = +1) or
// against it (-1, a control: the same sighting then agrees with the remembered direction).
TapeMap remembered_tape(double dir) {
  TapeMap m;
  Vec2 pts[20];
  // World x from -1.9 to 0 (dir +1) or from 0 to -1.9 (dir -1), in that order.
  for (int i = 0; i < 20; ++i) pts[i] = Vec2(dir > 0 ? -1.9 + 0.1 * i : -2.0 + 0.1 * i, 0.0);
  m.add(dir > 0 ? Pose2{0.0, 0.0, 0.0} : Pose2{-2.0, 0.0, kPi}, pts, 20);
  EXPECT_EQ(m.size(), 20U);
  return m;
}

// After losing the tape heading +x, the robot turns round in SEARCH; facing back (-x) it sees
// the tape it came along, running away from it: near to far is -x, against the remembered
// direction of travel. Returns the Sim after the search ended (or 6000 ticks).
Sim& search_seeing_tape_behind(Sim& s, const TapeMap& map) {
  lose_tape(s, 0.0);
  s.script = [&s, &map](BehaviorInput& in) {
    in.tape = &map;
    // The old tape is in view while the robot faces within 60 deg of -x.
    if (in.fresh_frame && std::cos(in.odom.yaw - kPi) > 0.5) {
      in.line_visible = true;
      const Vec2 near_w(in.odom.x - 0.8, 0.0);
      in.line_near = to_robot(in.odom, near_w);
      in.line_near_angle = wrap_angle(kPi - in.odom.yaw);
      in.track = StraightTape{Vec2::Zero(), kPi}.track(in.odom, 0.5);
    }
  };
  s.run_until([&] { return s.mb.state() != LineState::Search; }, 6000);
  return s;
}

TEST(LineBehaviorSearchDirection, TapeAlreadyTravelledSeenBackwardsIsNotFollowed) {
  Sim s(true);
  const TapeMap map = remembered_tape(+1.0);
  // The map is handed over when the search begins, so it must be in the input from the start.
  s.script = [&map](BehaviorInput& in) { in.tape = &map; };
  search_seeing_tape_behind(s, map);
  EXPECT_EQ(s.mb.state(), LineState::Fault);
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], Fault::LineNotFound);
  EXPECT_GT(s.mb.reversed_sightings(), 0U);
  EXPECT_EQ(s.mb.line_reacquired_events(), 0U);
}

TEST(LineBehaviorSearchDirection, SameSightingAgreeingWithTheMemoryIsFollowed) {
  // Control: remembered the other way round, the same sighting runs the way of travel.
  Sim s(true);
  const TapeMap map = remembered_tape(-1.0);
  s.script = [&map](BehaviorInput& in) { in.tape = &map; };
  search_seeing_tape_behind(s, map);
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_EQ(s.mb.reversed_sightings(), 0U);
  EXPECT_EQ(s.mb.line_reacquired_events(), 1U);
}

TEST(LineBehaviorSearchDirection, NewTapeOffTheRememberedPathIsFollowed) {
  // A sighting more than reacquire_on_path_m from the remembered tape is new tape, whatever way
  // it runs (a corner's next leg).
  Sim s(true);
  TapeMap map = remembered_tape(+1.0);
  s.script = [&map](BehaviorInput& in) { in.tape = &map; };
  lose_tape(s, 0.0);
  s.script = [&map](BehaviorInput& in) {
    in.tape = &map;
    if (in.fresh_frame && std::cos(in.odom.yaw - kPi / 2) > 0.9) {
      in.line_visible = true;
      in.line_near = to_robot(in.odom, Vec2(in.odom.x, in.odom.y + 0.8));
      in.line_near_angle = wrap_angle(kPi / 2 - in.odom.yaw);
      in.track = StraightTape{Vec2(in.odom.x, 0.0), kPi / 2}.track(in.odom, 0.5);
    }
  };
  ASSERT_TRUE(s.run_until([&] { return s.mb.state() != LineState::Search; }, 6000));
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_EQ(s.mb.reversed_sightings(), 0U);
}

TEST(LineBehaviorEndReach, TapeRunningOutNearAKnownEndMarkGoesToEnd) {
  // A short tail after a corner: the tape runs out of view 1.5 m before the mark it ends at.
  Sim s(false);
  s.start_on_tape();
  s.end_known = true;
  s.end_odom = Vec2(s.pose.x + 1.5, 0.0);
  s.tape_in_view = false;
  s.tape_in_map = false;
  ASSERT_TRUE(s.run_until([&] { return s.mb.state() != LineState::Follow; }, 100));
  EXPECT_EQ(s.mb.state(), LineState::End);
  EXPECT_EQ(s.mb.line_lost_events(), 0U);
}

TEST(LineBehaviorEndReach, AFarEndMarkDoesNotStopTheSearch) {
  Sim s(false);
  s.start_on_tape();
  s.end_known = true;
  s.end_odom = Vec2(s.pose.x + s.cfg.end_reach_m + 0.5, 0.0);
  s.tape_in_view = false;
  s.tape_in_map = false;
  ASSERT_TRUE(s.run_until([&] { return s.mb.state() != LineState::Follow; }, 100));
  EXPECT_EQ(s.mb.state(), LineState::Search);
}

TEST(LineBehaviorEndReach, EndMarkComingIntoViewDuringTheSearchEndsIt) {
  Sim s(false);
  lose_tape(s, 0.0);
  ASSERT_TRUE(s.run_until_phase("right", 2000));
  s.end_known = true;
  s.end_odom = Vec2(s.pose.x + 0.5, s.pose.y - 1.0);
  s.step();
  EXPECT_EQ(s.mb.state(), LineState::End);
  ASSERT_TRUE(s.run_until([&] { return s.mb.end_done(); }, 3000));
  EXPECT_LT((s.end_odom - Vec2(s.pose.x, s.pose.y)).norm(), 0.05);
}

// A short last leg after a corner: the end mark came into view from the side during the turn and
// is under the camera's blind zone once the robot faces it, so it was only ever glimpsed cut by
// the image's edge. When the tape runs out, END backs up until the mark is wholly in view.
TEST(LineBehaviorEndReveal, AGlimpsedMarkIsBackedUpToThenDrivenOnto) {
  Sim s(false);
  s.start_on_tape();
  const Vec2 mark(s.pose.x + 0.3, 0.0);
  const Vec2 from(s.pose.x, s.pose.y);
  s.tape_in_view = false;
  s.tape_in_map = false;
  double min_vx = 0.0;
  bool seen_whole = false;  // as FollowLineMission remembers it
  s.script = [&](BehaviorInput& in) {
    in.end_glimpsed = true;
    in.end_glimpse_odom = mark + Vec2(0.1, 0.05);  // the visible part's centroid: off the centre
    // Wholly in view once the camera's near edge (0.7 m ahead) has cleared the mark's near side.
    seen_whole = seen_whole || mark.x() - in.odom.x - 0.15 > 0.7;
    in.end_known = seen_whole;
    in.end_odom = seen_whole ? mark : Vec2::Zero();
    min_vx = std::fmin(min_vx, s.last.vx);
  };
  ASSERT_TRUE(s.run_until([&] { return s.mb.state() != LineState::Follow; }, 100));
  EXPECT_EQ(s.mb.state(), LineState::End);
  EXPECT_STREQ(s.mb.phase(), "reveal");
  ASSERT_TRUE(s.run_until([&] { return s.mb.end_done(); }, 3000));
  EXPECT_LT(min_vx, -0.1);  // it did back up
  EXPECT_LT((mark - Vec2(s.pose.x, s.pose.y)).norm(), 0.05);
  EXPECT_LT((from - Vec2(s.pose.x, s.pose.y)).norm(), 0.35);
  EXPECT_EQ(s.mb.line_lost_events(), 0U);
  EXPECT_EQ(s.phases, Phases({"find", "track", "reveal", "approach", "stopped"}));
}

// On the tape, which then runs out; a mark glimpsed `ahead` metres ahead (none when negative).
// Returns where the robot stood when the tape ran out.
Vec2 tape_ends_with_a_glimpse(Sim& s, double ahead) {
  s.start_on_tape();
  const Vec2 from(s.pose.x, s.pose.y);
  s.tape_in_view = false;
  s.tape_in_map = false;
  s.script = [from, ahead](BehaviorInput& in) {
    in.end_glimpsed = ahead >= 0.0;
    in.end_glimpse_odom = from + Vec2(ahead, 0.0);
  };
  return from;
}

TEST(LineBehaviorEndReveal, AMarkNeverSeenWholeEndsInTheSearchOnceBackedUpTheLimit) {
  Sim s(false);
  const Vec2 from = tape_ends_with_a_glimpse(s, 0.4);
  ASSERT_TRUE(s.run_until([&] { return s.mb.state() == LineState::Search; }, 2000));
  EXPECT_NEAR((from - Vec2(s.pose.x, s.pose.y)).norm(), s.cfg.end_reveal_m, 0.01);
  EXPECT_EQ(s.mb.line_lost_events(), 1U);
  EXPECT_TRUE(s.faults.empty());
}

TEST(LineBehaviorEndReveal, AGlimpseFarAwayOrNoneLeavesTheSearchAsItWas) {
  for (const double away : {-1.0, 1.2}) {
    SCOPED_TRACE(away);
    Sim s(false);
    tape_ends_with_a_glimpse(s, away);  // none at all, or one beyond end_reveal_m
    ASSERT_TRUE(s.run_until([&] { return s.mb.state() != LineState::Follow; }, 100));
    EXPECT_EQ(s.mb.state(), LineState::Search);
  }
}

}  // namespace
}  // namespace carril::fw
