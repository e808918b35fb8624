// LostExplorer: a lost robot turns in place; once a whole turn has not found it, it drives short
// legs toward the longest free corridor it saw, and looks round again after each.
#include "firmware/mission/LostExplorer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace carril::fw {
namespace {

constexpr double kDt = 0.01;   // [s]
constexpr double kTurn = 0.3;  // [rad/s]

LostExploreConfig driving() {
  LostExploreConfig c;
  c.speed_mps = 0.2;
  return c;
}

// A unicycle that does what the explorer asks; `free` says the corridor ahead at a pose.
struct World {
  Pose2 pose{1.0, 2.0, 0.5};
  std::function<double(const Pose2&)> free = [](const Pose2&) { return 5.0; };
  std::function<double(const Pose2&)> behind = [](const Pose2&) { return 5.0; };
  bool can_turn = true;
  std::function<bool(const Pose2&)> room;  // when set, replaces can_turn
  double turned = 0.0, driven = 0.0;

  Twist step(LostExplorer& e) {
    const Twist t = e.step(pose, room ? room(pose) : can_turn, free(pose), behind(pose));
    pose.yaw = wrap_angle(pose.yaw + t.wz * kDt);
    pose.x += t.vx * std::cos(pose.yaw) * kDt;
    pose.y += t.vx * std::sin(pose.yaw) * kDt;
    turned += std::fabs(t.wz) * kDt;
    driven += std::fabs(t.vx) * kDt;
    return t;
  }
  // Steps until the explorer first asks to drive (or `max_s` passes); the time taken [s].
  double until_driving(LostExplorer& e, double max_s) {
    for (double t = 0.0; t < max_s; t += kDt) {
      if (step(e).vx != 0.0) return t;
    }
    return max_s;
  }
  // Steps while the explorer stays in `phase`, at most `max_s` (a broken explorer fails, not
  // hangs) [s].
  void while_in(LostExplorer& e, LostExplorer::Phase phase, double max_s = 60.0) {
    for (double t = 0.0; t < max_s && e.phase() == phase; t += kDt) step(e);
  }
};

// Open only round heading `h` (within 0.2 rad): 3 m there, 0.4 m elsewhere.
std::function<double(const Pose2&)> open_toward(double h) {
  return [h](const Pose2& p) { return std::fabs(wrap_angle(p.yaw - h)) < 0.2 ? 3.0 : 0.4; };
}

TEST(LostExplorerTest, AWholeTurnFirstThenALegTowardTheOpenHeading) {
  LostExplorer e{driving(), kTurn};
  World w;
  w.free = open_toward(-2.0);
  const double t = w.until_driving(e, 60.0);
  // The whole turn (2 pi at 0.3 rad/s: 20.9 s), then on round to face -2.0 rad.
  EXPECT_GT(w.turned, 2.0 * kPi);
  EXPECT_LT(w.turned, 4.0 * kPi);
  EXPECT_GT(t, 2.0 * kPi / kTurn);
  EXPECT_EQ(e.phase(), LostExplorer::Phase::Drive);
  EXPECT_EQ(e.legs(), 1U);
  // The middle of the open sector, within the facing tolerance.
  EXPECT_NEAR(wrap_angle(w.pose.yaw - (-2.0)), 0.0, 0.06);
  // The leg: at 0.2 m/s, straight, then a new look-round after leg_m.
  const Pose2 start = w.pose;
  double leg_s = 0.0;
  while (e.phase() == LostExplorer::Phase::Drive && leg_s < 30.0) {
    const Twist tw = w.step(e);
    if (e.phase() == LostExplorer::Phase::Drive) {
      EXPECT_DOUBLE_EQ(tw.vx, 0.2);
    }
    leg_s += kDt;
  }
  EXPECT_NEAR(std::hypot(w.pose.x - start.x, w.pose.y - start.y), 2.0, 0.01);
  EXPECT_NEAR(wrap_angle(w.pose.yaw - (-2.0)), 0.0, 0.01);  // held the leg's heading
  EXPECT_EQ(e.phase(), LostExplorer::Phase::Turn);
  // The next leg again waits for a whole turn.
  const double turned = w.turned;
  w.free = [](const Pose2&) { return 5.0; };
  w.until_driving(e, 60.0);
  EXPECT_GT(w.turned - turned, 2.0 * kPi);
  EXPECT_EQ(e.legs(), 2U);
}

TEST(LostExplorerTest, AtSpeedZeroOrWithNoRoomAheadItOnlyTurns) {
  for (const bool zero_speed : {true, false}) {
    LostExplorer e{zero_speed ? LostExploreConfig{} : driving(), kTurn};
    World w;
    if (!zero_speed) w.free = [](const Pose2&) { return 0.9; };  // below min_free_m (1 m)
    EXPECT_EQ(w.until_driving(e, 90.0), 90.0) << zero_speed;
    EXPECT_NEAR(w.turned, 90.0 * kTurn, 0.01) << zero_speed;
    EXPECT_EQ(e.legs(), 0U);
  }
}

TEST(LostExplorerTest, WithoutRoomToTurnItStandsStillAndCountsNoTurn) {
  LostExplorer e{driving(), kTurn};
  World w;
  w.can_turn = false;
  for (int i = 0; i < 100; ++i) {
    const Twist t = w.step(e);
    EXPECT_EQ(t.wz, 0.0);
    EXPECT_EQ(t.vx, 0.0);
  }
  // Room again: the whole turn is still ahead of it.
  w.can_turn = true;
  EXPECT_GT(w.until_driving(e, 60.0), 2.0 * kPi / kTurn - 0.05);
}

TEST(LostExplorerTest, ALegEndsWhereTheCorridorCloses) {
  LostExplorer e{driving(), kTurn};
  World w;
  // Free up to x = 2.0 m ahead of a robot driving along +x from x = 1.
  w.free = [](const Pose2& p) { return std::fabs(wrap_angle(p.yaw)) < 0.2 ? 2.0 - p.x : 0.3; };
  w.until_driving(e, 60.0);
  ASSERT_EQ(e.phase(), LostExplorer::Phase::Drive);
  w.while_in(e, LostExplorer::Phase::Drive);
  // Stopped once less than stop_free_m (0.6 m) was left, well short of the 2 m leg.
  EXPECT_NEAR(w.pose.x, 2.0 - 0.6, 0.01);
}

TEST(LostExplorerTest, TheNextLegDoesNotGoBackTheWayTheLastCame) {
  LostExplorer e{driving(), kTurn};
  World w;
  w.free = open_toward(0.0);
  w.until_driving(e, 60.0);
  w.while_in(e, LostExplorer::Phase::Drive);
  // Now the way back (pi) is the longest corridor; one at +pi/2 has room enough.
  w.free = [](const Pose2& p) {
    if (std::fabs(wrap_angle(p.yaw - kPi)) < 0.2) return 10.0;
    if (std::fabs(wrap_angle(p.yaw - kPi / 2.0)) < 0.2) return 1.5;
    return 0.4;
  };
  w.until_driving(e, 90.0);
  ASSERT_EQ(e.legs(), 2U);
  EXPECT_NEAR(wrap_angle(w.pose.yaw - kPi / 2.0), 0.0, 0.06);
  // With nowhere else to go it does go back.
  w.while_in(e, LostExplorer::Phase::Drive);
  const double last = w.pose.yaw;
  w.free = [last](const Pose2& p) {
    return std::fabs(wrap_angle(p.yaw - last - kPi)) < 0.2 ? 3.0 : 0.4;
  };
  w.until_driving(e, 90.0);
  ASSERT_EQ(e.legs(), 3U);
  EXPECT_NEAR(std::fabs(wrap_angle(w.pose.yaw - last)), kPi, 0.06);
}

TEST(LostExplorerTest, WhatClosedWhileItTurnedToFaceItIsNotDriven) {
  LostExplorer e{driving(), kTurn};
  World w;
  w.free = open_toward(-2.0);
  // The whole turn saw the opening; then something stands in it (a person walking by).
  w.while_in(e, LostExplorer::Phase::Turn);
  ASSERT_EQ(e.phase(), LostExplorer::Phase::Face);
  w.free = [](const Pose2&) { return 0.4; };
  EXPECT_EQ(w.until_driving(e, 60.0), 60.0);
  EXPECT_EQ(e.legs(), 0U);
  EXPECT_EQ(e.phase(), LostExplorer::Phase::Turn);
}

TEST(LostExplorerTest, FoundAgainTheNextLossStartsWithAWholeTurn) {
  LostExplorer e{driving(), kTurn};
  World w;
  w.until_driving(e, 60.0);
  ASSERT_EQ(e.phase(), LostExplorer::Phase::Drive);
  e.reset();
  EXPECT_EQ(e.phase(), LostExplorer::Phase::Turn);
  const double turned = w.turned;
  w.until_driving(e, 60.0);
  EXPECT_GT(w.turned - turned, 2.0 * kPi);
}

// Open only along +x from (1, 2); past x = 1.5 there is no room to turn (a dead end between
// counters), while at the leg's start there is. Turns, then drives the leg to its end.
void into_dead_end(World& w, LostExplorer& e) {
  w.pose = {1.0, 2.0, 0.5};
  w.free = [](const Pose2& p) {
    return std::fabs(wrap_angle(p.yaw)) < 0.2 ? std::fmax(0.0, 2.2 - p.x) : 0.4;
  };
  w.room = [](const Pose2& p) { return p.x < 1.5; };
  w.until_driving(e, 60.0);
  w.while_in(e, LostExplorer::Phase::Drive);
}

TEST(LostExplorerTest, ALegThatEndsWithNoRoomToTurnIsBackedToItsStart) {
  LostExplorer e{driving(), kTurn};
  World w;
  into_dead_end(w, e);
  // The leg ended 0.6 m short of x = 2.2, past the room to turn.
  ASSERT_NEAR(w.pose.x, 1.6, 0.01);
  EXPECT_EQ(e.backs(), 0U);
  // Then it backs along the leg, holding its heading, and not just until there is room: to the
  // leg's start (1, 2), where it turned all round.
  double min_vx = 0.0;
  for (int i = 0; i < 1000 && w.pose.x > 1.0 + 0.03; ++i) min_vx = std::fmin(min_vx, w.step(e).vx);
  EXPECT_EQ(min_vx, -0.2);
  EXPECT_EQ(e.backs(), 1U);
  for (int i = 0; i < 100; ++i) w.step(e);
  EXPECT_NEAR(w.pose.x, 1.0, 0.03);
  EXPECT_NEAR(w.pose.y, 2.0, 0.03);
  EXPECT_EQ(e.phase(), LostExplorer::Phase::Turn);
  // There it looks round again, and with another way open the next leg takes it, not the dead end.
  w.free = [](const Pose2& p) {
    if (std::fabs(wrap_angle(p.yaw)) < 0.2) return std::fmax(0.0, 2.2 - p.x);
    return std::fabs(wrap_angle(p.yaw - 2.0)) < 0.2 ? 1.1 : 0.4;
  };
  const double turned = w.turned;
  w.until_driving(e, 60.0);
  EXPECT_GT(w.turned - turned, 2.0 * kPi - 0.1);
  EXPECT_EQ(e.legs(), 2U);
  EXPECT_NEAR(wrap_angle(w.pose.yaw - 2.0), 0.0, 0.2);
  EXPECT_EQ(e.backs(), 1U);
}

TEST(LostExplorerTest, BackingEndsAtTheLegsStartEvenOffItsTrack) {
  // The wheels slipped 5 cm sideways at the leg's end: backing along the leg's heading passes the
  // start 5 cm to its side. It stops there, level with the start, and does not back on past it
  // (nothing stands behind: it would back on until something did).
  LostExplorer e{driving(), kTurn};
  World w;
  into_dead_end(w, e);
  w.pose.y += 0.05;
  bool backed = false;
  for (int i = 0; i < 3000; ++i) {
    const Twist t = w.step(e);
    if (t.vx < 0.0) {
      backed = true;
    } else if (backed) {
      break;  // the first step after the backing
    }
  }
  ASSERT_TRUE(backed);
  EXPECT_EQ(e.backs(), 1U);
  EXPECT_NEAR(w.pose.x, 1.0, 0.03);
  EXPECT_NEAR(w.pose.y, 2.05, 0.01);
  EXPECT_NE(e.phase(), LostExplorer::Phase::Drive);
}

TEST(LostExplorerTest, BackingStopsForWhatIsBehindAndNeverStartsWithoutALeg) {
  LostExplorer e{driving(), kTurn};
  World w;
  into_dead_end(w, e);
  // Something stands 0.2 m behind where the leg ended (x = 1.6): it backs 0.05 m and stops
  // 0.15 m short of it, still with no room to turn, and waits.
  w.behind = [](const Pose2& p) { return p.x - 1.4; };
  for (int i = 0; i < 1000; ++i) w.step(e);
  EXPECT_NEAR(w.pose.x, 1.55, 0.01);
  EXPECT_NEAR(wrap_angle(w.pose.yaw), 0.0, 0.01);
  // It goes away: the robot backs on to the leg's start, still holding the leg's heading.
  w.behind = [](const Pose2&) { return 5.0; };
  double yaw_off = 0.0;
  for (int i = 0; i < 1000 && w.pose.x > 1.0 + 0.03; ++i) {
    w.step(e);
    yaw_off = std::fmax(yaw_off, std::fabs(wrap_angle(w.pose.yaw)));
  }
  EXPECT_NEAR(w.pose.x, 1.0, 0.03);
  EXPECT_LT(yaw_off, 0.05);
  EXPECT_EQ(e.backs(), 1U);
  // Nothing known behind (0): it stands where it is.
  World still;
  LostExplorer e2{driving(), kTurn};
  into_dead_end(still, e2);
  still.behind = [](const Pose2&) { return 0.0; };
  const double x = still.pose.x;
  for (int i = 0; i < 300; ++i) EXPECT_EQ(still.step(e2).vx, 0.0);
  EXPECT_EQ(still.pose.x, x);
  EXPECT_EQ(e2.backs(), 0U);
}

TEST(LostExplorerTest, ConfigErrorsNameTheField) {
  EXPECT_TRUE(driving().validate().is_ok());
  LostExploreConfig c = driving();
  c.stop_free_m = c.min_free_m;
  const Status s = c.validate();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("runner.lost_explore.stop_free_m"), std::string::npos)
      << s.message();
  c = driving();
  c.speed_mps = -0.1;
  EXPECT_NE(std::string(c.validate().message()).find("speed_mps"), std::string::npos);
}

}  // namespace
}  // namespace carril::fw
