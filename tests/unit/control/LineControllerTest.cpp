// LineController: the marks, line_priority and pid strategies on hand-made TrackStates.
#include "firmware/control/LineController.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::fw {
namespace {

constexpr double kDt = 0.01;  // [s]

// The robot on a straight tape, plenty of it ahead.
TrackState on_tape(double lateral = 0.0, double heading = 0.0, Vec2 la = Vec2(0.3, 0.0)) {
  TrackState t;
  t.valid = true;
  t.lateral_m = lateral;
  t.heading_err_rad = heading;
  t.lookahead = la;
  t.remaining_m = 3.0;
  return t;
}

StrategyConfig strategy(Strategy s) {
  StrategyConfig c;
  c.strategy = s;
  return c;
}

// ---------------------------------------------------------------------------------------------
// marks

TEST(LineControllerTest, MarksStraightAheadIsFullSpeedWithoutTurning) {
  for (const bool holo : {false, true}) {
    LineController lc(strategy(Strategy::Marks), holo);
    const Twist t = lc.follow(on_tape(), kDt);
    EXPECT_NEAR(t.wz, 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(t.vx, lc.config().speed_mps);
    EXPECT_EQ(t.vy, 0.0);
  }
}

TEST(LineControllerTest, MarksTurnsTowardTheLookahead) {
  LineController lc(strategy(Strategy::Marks), false);
  const Twist l = lc.follow(on_tape(0.0, 0.0, Vec2(0.3, 0.08)), kDt);
  EXPECT_GT(l.wz, 0.0);
  EXPECT_GT(l.vx, 0.0);
  EXPECT_LT(l.vx, lc.config().speed_mps);
  // Pure pursuit: the arc through the look-ahead point.
  const double d = std::hypot(0.3, 0.08), b = std::atan2(0.08, 0.3);
  EXPECT_NEAR(l.wz, 2.0 * l.vx * std::sin(b) / d, 1e-12);
  const Twist r = lc.follow(on_tape(0.0, 0.0, Vec2(0.3, -0.08)), kDt);
  EXPECT_LT(r.wz, 0.0);
  EXPECT_NEAR(r.wz, -l.wz, 1e-12);
}

TEST(LineControllerTest, MarksHolonomicClosesTheLateralOffsetDirectly) {
  LineController lc(strategy(Strategy::Marks), true);
  const Twist t = lc.follow(on_tape(0.1, 0.0, Vec2(0.3, 0.1)), kDt);
  EXPECT_GT(t.vy, 0.0);
  EXPECT_NEAR(t.vy, lc.config().lp_k_lateral * 0.1, 1e-12);
  const Twist big = lc.follow(on_tape(-1.0, 0.0, Vec2(0.3, -1.0)), kDt);
  EXPECT_GE(big.vy, -lc.config().speed_mps);  // clamped to the speed
  EXPECT_LT(big.vy, 0.0);
}

TEST(LineControllerTest, NoFasterThanTheRememberedTapeAllows) {
  for (const Strategy s : {Strategy::Marks, Strategy::LinePriority, Strategy::Pid}) {
    LineController lc(strategy(s), true);
    TrackState t = on_tape();
    t.remaining_m = 0.1;
    const Twist v = lc.follow(t, kDt);
    EXPECT_LE(std::hypot(v.vx, v.vy), 1.2 * 0.1 + 1e-12) << strategy_name(s);
  }
}

// ---------------------------------------------------------------------------------------------
// line_priority

TEST(LineControllerTest, LinePriorityStrafesTowardTheTape) {
  LineController lc(strategy(Strategy::LinePriority), true);
  const Twist l = lc.follow(on_tape(0.1), kDt);
  EXPECT_GT(l.vy, 0.0);
  EXPECT_NEAR(l.vy, lc.config().lp_k_lateral * 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(l.vx, lc.config().speed_mps);
  EXPECT_NEAR(l.wz, 0.0, 1e-12);
  const Twist r = lc.follow(on_tape(-0.1), kDt);
  EXPECT_LT(r.vy, 0.0);
}

TEST(LineControllerTest, LinePriorityTurnsWithTheTapeAngle) {
  LineController lc(strategy(Strategy::LinePriority), true);
  const Twist l = lc.follow(on_tape(0.0, 0.2), kDt);
  EXPECT_GT(l.wz, 0.0);
  EXPECT_NEAR(l.wz, lc.config().lp_k_angle * 0.2, 1e-12);
  // Moves along the tape's direction.
  EXPECT_NEAR(std::atan2(l.vy, l.vx), 0.2, 1e-12);
  EXPECT_LT(lc.follow(on_tape(0.0, -0.2), kDt).wz, 0.0);
}

TEST(LineControllerTest, LinePrioritySlowsForCorners) {
  LineController lc(strategy(Strategy::LinePriority), true);
  const StrategyConfig& c = lc.config();
  TrackState t = on_tape();
  t.corner_turn_rad = c.corner_turn_rad + 0.3;
  t.corner_dist_m = 0.0;
  Twist v = lc.follow(t, kDt);
  EXPECT_LE(std::hypot(v.vx, v.vy), c.corner_min_speed_mps + 1e-12);
  EXPECT_GT(v.vx, 0.0);
  // Half-way through the slowing distance: half-way between the speeds.
  t.corner_turn_rad = -(c.corner_turn_rad + 0.3);
  t.corner_dist_m = 0.5 * c.corner_slow_m;
  v = lc.follow(t, kDt);
  EXPECT_NEAR(v.vx, 0.5 * (c.corner_min_speed_mps + c.speed_mps), 1e-12);
  // A gentle bend is no corner.
  t.corner_turn_rad = 0.5 * c.corner_turn_rad;
  t.corner_dist_m = 0.0;
  EXPECT_DOUBLE_EQ(lc.follow(t, kDt).vx, c.speed_mps);
  // Curvature: lateral acceleration limited to 0.35 m/s^2.
  TrackState k = on_tape();
  k.curvature_ahead = 2.0;
  EXPECT_NEAR(lc.follow(k, kDt).vx, std::sqrt(0.35 / 2.0), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// pid

TEST(LineControllerTest, PidTurnsTowardTheTapeAhead) {
  LineController lc(strategy(Strategy::Pid), false);
  const StrategyConfig& c = lc.config();
  const Twist l = lc.follow(on_tape(0.0, 0.0, Vec2(0.3, 0.05)), kDt);  // error 0.2: straight
  EXPECT_GT(l.wz, 0.0);
  EXPECT_NEAR(l.wz, c.pid_straight.kp * 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(l.vx, c.pid_straight.speed_mps);
  lc.reset();
  EXPECT_LT(lc.follow(on_tape(0.0, 0.0, Vec2(0.3, -0.05)), kDt).wz, 0.0);
}

TEST(LineControllerTest, PidCurveGainsAboveTheThreshold) {
  LineController lc(strategy(Strategy::Pid), false);
  const StrategyConfig& c = lc.config();
  const double e = 0.3;  // > pid_curve_threshold (0.25)
  const Twist t = lc.follow(on_tape(0.0, 0.0, Vec2(0.3, e * c.pid_error_scale_m)), kDt);
  EXPECT_NEAR(t.wz, c.pid_curve.kp * e, 1e-12);
  EXPECT_NEAR(t.vx, c.pid_curve.speed_mps / (std::fabs(t.wz) + 1.0), 1e-12);
}

TEST(LineControllerTest, PidDerivativeOnTheErrorChange) {
  LineController lc(strategy(Strategy::Pid), false);
  const StrategyConfig& c = lc.config();
  lc.follow(on_tape(0.0, 0.0, Vec2(0.3, 0.0)), kDt);
  const Twist t = lc.follow(on_tape(0.0, 0.0, Vec2(0.3, 0.01)), kDt);  // e: 0 -> 0.04
  EXPECT_NEAR(t.wz, c.pid_straight.kp * 0.04 + c.pid_straight.kd * 0.04 / kDt, 1e-9);
}

TEST(LineControllerTest, PidLostTurnsTowardTheLastError) {
  LineController lc(strategy(Strategy::Pid), false);
  EXPECT_EQ(lc.lost(kDt).wz, 0.0);  // no error yet: nothing to go on
  lc.follow(on_tape(0.0, 0.0, Vec2(0.3, 0.02)), kDt);
  const Twist l = lc.lost(kDt);
  EXPECT_GT(l.wz, 0.0);
  EXPECT_GT(l.vx, 0.0);
  EXPECT_LT(l.vx, lc.config().pid_curve.speed_mps);
  lc.follow(on_tape(0.0, 0.0, Vec2(0.3, -0.02)), kDt);
  const Twist r = lc.lost(kDt);
  EXPECT_LT(r.wz, 0.0);
  EXPECT_DOUBLE_EQ(r.wz, -l.wz);
  lc.reset();
  EXPECT_EQ(lc.lost(kDt).wz, 0.0);
}

TEST(LineControllerTest, OtherStrategiesStopWhenLost) {
  for (const Strategy s : {Strategy::Marks, Strategy::LinePriority}) {
    LineController lc(strategy(s), true);
    lc.follow(on_tape(0.1, 0.1, Vec2(0.3, 0.1)), kDt);
    const Twist t = lc.lost(kDt);
    EXPECT_EQ(t.vx, 0.0);
    EXPECT_EQ(t.vy, 0.0);
    EXPECT_EQ(t.wz, 0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// Pivot

TEST(LineControllerTest, DifferentialPivotsOnLargeHeadingError) {
  for (const Strategy s : {Strategy::Marks, Strategy::Pid}) {
    LineController lc(strategy(s), false);
    const double h = lc.config().pivot_heading_rad + 0.1;
    const Twist l = lc.follow(on_tape(0.0, h, Vec2(0.2, 0.2)), kDt);
    EXPECT_EQ(l.vx, 0.0) << strategy_name(s);
    EXPECT_EQ(l.vy, 0.0);
    EXPECT_GT(l.wz, 0.0);
    EXPECT_LE(l.wz, lc.config().max_yaw_rate_radps);
    const Twist r = lc.follow(on_tape(0.0, -h, Vec2(0.2, -0.2)), kDt);
    EXPECT_EQ(r.vx, 0.0);
    EXPECT_LT(r.wz, 0.0);
    // Just under the threshold: keeps moving.
    const double under = lc.config().pivot_heading_rad - 0.05;
    EXPECT_GT(lc.follow(on_tape(0.0, under, Vec2(0.3, 0.05)), kDt).vx, 0.0);
  }
}

TEST(LineControllerTest, HolonomicDoesNotPivot) {
  LineController lc(strategy(Strategy::Marks), true);
  const Twist t = lc.follow(on_tape(0.0, 0.8, Vec2(0.2, 0.2)), kDt);
  EXPECT_GT(t.vx, 0.0);
}

}  // namespace
}  // namespace carril::fw
