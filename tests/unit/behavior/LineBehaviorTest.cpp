// LineBehavior, driven tick by tick: START, END and the phase log. FOLLOW and SEARCH are in
// LineFollowSearchTest.cpp, AVOID in LineAvoidTest.cpp.
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

// ---------------------------------------------------------------------------------------------
// START

TEST(LineBehaviorTest, WaitsUntilDrivesCameraAndScannerAreReady) {
  Sim s(false);
  s.drives = false;
  for (int i = 0; i < 50; ++i) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Start);
    ASSERT_STREQ(s.mb.phase(), "wait");
    expect_still(s.out.twist);
  }
  s.drives = true;
  s.step();
  EXPECT_EQ(s.mb.state(), LineState::Start);
  EXPECT_STREQ(s.mb.phase(), "find");
  EXPECT_TRUE(s.faults.empty());
  EXPECT_EQ(s.phases, Phases({"find"}));
}

struct TimeoutCase {
  bool drives, camera, scanner, imu;
  Fault expect;
};

class LineBehaviorStartTimeout : public testing::TestWithParam<TimeoutCase> {};

TEST_P(LineBehaviorStartTimeout, FaultsAfterInitTimeout) {
  const TimeoutCase c = GetParam();
  Sim s(true);
  s.drives = c.drives;
  s.camera = c.camera;
  s.scanner = c.scanner;
  s.imu = c.imu;
  while (s.t < s.cfg.init_timeout_s - 0.005) {
    s.step();
    ASSERT_EQ(s.mb.state(), LineState::Start) << "t=" << s.last_in.t_s;
  }
  ASSERT_TRUE(s.run_until_state(LineState::Fault, 3));
  EXPECT_GT(s.last_in.t_s, s.cfg.init_timeout_s);
  EXPECT_STREQ(s.mb.phase(), "stopped");
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], c.expect) << fault_name(s.faults[0]);
  // Latched: zero twist, the fault reported once, nothing moves on.
  for (int i = 0; i < 100; ++i) {
    s.step();
    expect_still(s.out.twist);
  }
  EXPECT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.mb.state(), LineState::Fault);
  EXPECT_EQ(s.phases, Phases({"stopped"}));
}

INSTANTIATE_TEST_SUITE_P(
    Missing, LineBehaviorStartTimeout,
    testing::Values(TimeoutCase{false, true, true, true, Fault::DriveEnableTimeout},
                    TimeoutCase{false, false, false, false, Fault::DriveEnableTimeout},
                    TimeoutCase{true, false, true, true, Fault::CameraTimeout},
                    TimeoutCase{true, false, false, true, Fault::CameraTimeout},
                    TimeoutCase{true, true, false, true, Fault::ScannerTimeout},
                    TimeoutCase{true, true, false, false, Fault::ScannerTimeout},
                    TimeoutCase{true, true, true, false, Fault::ImuTimeout}));

TEST(LineBehaviorTest, FindFollowsAtOnceWhenOnTheTape) {
  Sim s(false);
  s.start_on_tape();
  EXPECT_EQ(s.mb.state(), LineState::Follow);
  EXPECT_STREQ(s.mb.phase(), "track");
  EXPECT_EQ(s.phases, Phases({"find", "track"}));
  EXPECT_EQ(s.mb.line_lost_events(), 0U);
  EXPECT_EQ(s.mb.line_reacquired_events(), 0U);
  EXPECT_EQ(s.mb.obstacles_avoided(), 0U);
}

TEST(LineBehaviorTest, FindOnTapeThresholds) {
  struct Case {
    double y, angle;
    bool direct;
  };
  for (const Case c : {Case{0.10, 0.0, true}, Case{-0.14, 0.3, true}, Case{0.0, -0.45, true},
                       Case{0.2, 0.0, false}, Case{-0.2, 0.0, false}, Case{0.0, 0.6, false},
                       Case{0.05, -0.7, false}}) {
    Sim s(false);
    s.script = [&](BehaviorInput& in) {
      in.line_near = Vec2(0.8, c.y);
      in.line_near_angle = c.angle;
    };
    s.start_on_tape();
    EXPECT_EQ(s.mb.state(), c.direct ? LineState::Follow : LineState::Start)
        << "y=" << c.y << " angle=" << c.angle;
    EXPECT_STREQ(s.mb.phase(), c.direct ? "track" : "approach");
  }
}

// Tape off to one side: drive onto its nearest visible point, face along it, follow.
class LineBehaviorApproach : public testing::TestWithParam<bool> {};

TEST_P(LineBehaviorApproach, ParallelTapeToTheLeft) {
  Sim s(GetParam());
  s.tape.p0 = Vec2(0.0, 0.5);
  s.step();
  s.step();
  ASSERT_STREQ(s.mb.phase(), "approach");
  const Vec2 target(0.7, 0.5);  // the nearest visible tape point, odometry frame
  ASSERT_TRUE(s.run_until_state(LineState::Follow, 3000));
  EXPECT_EQ(s.phases, Phases({"find", "approach", "align", "track"}));
  EXPECT_LT((Vec2(s.pose.x, s.pose.y) - target).norm(), 0.045);
  EXPECT_LT(std::fabs(wrap_angle(s.pose.yaw - 0.0)), s.cfg.align_tolerance_rad + 1e-9);
}

TEST_P(LineBehaviorApproach, TapeCrossingAtAnAngle) {
  const bool holo = GetParam();
  Sim s(holo);
  s.tape.p0 = Vec2(0.8, 0.0);
  s.tape.h = 1.0;
  s.step();
  s.step();
  ASSERT_STREQ(s.mb.phase(), "approach");
  const Vec2 target = to_world(Pose2{}, s.last_in.line_near);
  bool translated_in_align = false, turned_in_approach = false;
  ASSERT_TRUE(s.run_until(
      [&] {
        if (std::string(s.mb.phase()) == "align" && s.last_in.odom.x != s.pose.x)
          translated_in_align = true;
        if (std::string(s.mb.phase()) == "approach" && s.out.twist.wz != 0.0)
          turned_in_approach = true;
        return s.mb.state() == LineState::Follow;
      },
      3000));
  EXPECT_EQ(s.phases, Phases({"find", "approach", "align", "track"}));
  EXPECT_LT((Vec2(s.pose.x, s.pose.y) - target).norm(), 0.045);
  EXPECT_NEAR(s.pose.yaw, 1.0, s.cfg.align_tolerance_rad + 1e-9);
  EXPECT_FALSE(translated_in_align);
  EXPECT_TRUE(turned_in_approach);  // holonomic: turns while translating; differential: first
}

INSTANTIATE_TEST_SUITE_P(Drive, LineBehaviorApproach, testing::Values(true, false),
                         [](const auto& i) { return i.param ? "Holonomic" : "Differential"; });

TEST(LineBehaviorTest, FindTurnsOnTheSpotWithoutTape) {
  Sim s(false);
  s.tape_in_view = false;
  s.step();
  for (int i = 0; i < 200; ++i) {
    s.step();
    ASSERT_STREQ(s.mb.phase(), "find");
    EXPECT_GT(s.out.twist.wz, 0.0);
    EXPECT_DOUBLE_EQ(s.out.twist.wz, s.cfg.search_yaw_rate_radps);
    EXPECT_EQ(s.out.twist.vx, 0.0);
    EXPECT_EQ(s.out.twist.vy, 0.0);
  }
  EXPECT_DOUBLE_EQ(s.pose.x, 0.0);
  EXPECT_DOUBLE_EQ(s.pose.y, 0.0);
}

TEST(LineBehaviorTest, FindGivesUpAfterMaxTurn) {
  Sim s(true);
  s.tape_in_view = false;
  double turned = 0.0;
  ASSERT_TRUE(s.run_until(
      [&] {
        turned += std::fabs(s.out.twist.wz) * kDt;
        return s.mb.state() != LineState::Start;
      },
      5000));
  EXPECT_EQ(s.mb.state(), LineState::Fault);
  EXPECT_STREQ(s.mb.phase(), "stopped");
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0], Fault::LineNotFound);
  EXPECT_NEAR(turned, s.cfg.start_max_turn_rad, 0.02);
  EXPECT_EQ(s.phases, Phases({"find", "stopped"}));
}

TEST(LineBehaviorTest, FindStopsTurningWhenTapeComesIntoView) {
  Sim s(false);
  s.tape_in_view = false;
  s.script = [&](BehaviorInput& in) {
    if (in.odom.yaw > 1.2 && in.fresh_frame) {
      in.line_visible = true;
      in.line_near = Vec2(0.8, 0.02);
      in.line_near_angle = 0.1;
    }
  };
  ASSERT_TRUE(s.run_until_state(LineState::Follow, 1000));
  EXPECT_NEAR(s.pose.yaw, 1.2, 0.01);
  EXPECT_EQ(s.phases, Phases({"find", "track"}));
}

// ---------------------------------------------------------------------------------------------
// END

class LineBehaviorEnd : public testing::TestWithParam<bool> {};

TEST_P(LineBehaviorEnd, DrivesOntoTheMarkAndStops) {
  const bool holo = GetParam();
  Sim s(holo);
  s.end_known = true;
  s.end_odom = Vec2(1.6, 0.08);
  s.start_on_tape();
  ASSERT_TRUE(s.run_until_state(LineState::End, 1000));
  s.step();
  // Toward the mark, which is ahead and a little to the left.
  const Vec2 e = to_robot(s.last_in.odom, s.end_odom);
  EXPECT_GT(s.out.twist.vx, 0.0);
  if (holo) {
    EXPECT_GT(s.out.twist.vy, 0.0);
    EXPECT_EQ(s.out.twist.wz, 0.0);
    EXPECT_NEAR(std::atan2(s.out.twist.vy, s.out.twist.vx), std::atan2(e.y(), e.x()), 1e-9);
  } else {
    EXPECT_EQ(s.out.twist.vy, 0.0);
    EXPECT_GT(s.out.twist.wz, 0.0);
  }
  EXPECT_LE(std::hypot(s.out.twist.vx, s.out.twist.vy), s.cfg.end_speed_mps + 1e-9);
  ASSERT_TRUE(s.run_until([&] { return s.mb.end_done(); }, 3000));
  EXPECT_STREQ(s.mb.phase(), "stopped");
  expect_still(s.out.twist);
  EXPECT_LT((Vec2(s.pose.x, s.pose.y) - s.end_odom).norm(), s.cfg.end_tolerance_m);
  const Pose2 stop = s.pose;
  for (int i = 0; i < 100; ++i) {
    s.step();
    expect_still(s.out.twist);
  }
  EXPECT_EQ(s.pose.x, stop.x);
  EXPECT_EQ(s.pose.y, stop.y);
  EXPECT_EQ(s.mb.state(), LineState::End);
  EXPECT_TRUE(s.faults.empty());
  EXPECT_EQ(s.phases, Phases({"find", "track", "approach", "stopped"}));
}

INSTANTIATE_TEST_SUITE_P(Drive, LineBehaviorEnd, testing::Values(true, false),
                         [](const auto& i) { return i.param ? "Holonomic" : "Differential"; });

// ---------------------------------------------------------------------------------------------
// Phase log

TEST(LineBehaviorTest, TakePhaseChangeReturnsEachNewPhaseOnce) {
  BehaviorConfig cfg;
  LineController line(StrategyConfig{}, false);
  BypassPlanner planner(cfg.avoid, Footprint{}, false);
  LineBehavior mb(cfg, line, planner, false);
  EXPECT_EQ(mb.take_phase_change(), nullptr);
  BehaviorInput in;
  in.drives_ready = in.camera_ready = in.scanner_ready = true;
  mb.step(in, kDt);
  const char* p = mb.take_phase_change();
  ASSERT_NE(p, nullptr);
  EXPECT_STREQ(p, "find");
  EXPECT_EQ(mb.take_phase_change(), nullptr);
  mb.step(in, kDt);  // still finding: no new phase
  EXPECT_EQ(mb.take_phase_change(), nullptr);
  in.t_s = 0.01;
  in.fresh_frame = in.line_visible = true;
  in.line_near = Vec2(0.8, 0.0);
  mb.step(in, kDt);
  p = mb.take_phase_change();
  ASSERT_NE(p, nullptr);
  EXPECT_STREQ(p, "track");
  EXPECT_EQ(mb.take_phase_change(), nullptr);
}

}  // namespace
}  // namespace carril::fw
