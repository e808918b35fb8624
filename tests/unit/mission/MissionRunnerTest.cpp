// MissionRunner: enters the mission once, hands it its context, raises its faults with the state
// they struck in, stops a guarded motion for an obstacle ahead, and holds the safe stop.
#include "firmware/mission/MissionRunner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tests/unit/mission/ScriptedMission.hpp"

namespace carril::fw {
namespace {

struct RecordingSink final : FaultSink {
  void raise(Fault f, std::uint16_t code, const char* in_state) override {
    raised.push_back({f, code, in_state ? in_state : "(current)"});
    if (latch) fault = f;
  }
  bool latched() const override { return fault != Fault::None; }
  struct Raised {
    Fault f;
    std::uint16_t code;
    std::string in_state;
  };
  std::vector<Raised> raised;
  Fault fault = Fault::None;
  bool latch = true;
};

// A scan with one return straight ahead of a sensor at the robot centre, `range` away.
hal::LaserScan scan_with_point_ahead(double range) {
  hal::LaserScan s;
  s.seq = 1;
  s.count = 3;
  s.angle_min_rad = -0.01F;
  s.angle_increment_rad = 0.01F;
  s.range_min_m = 0.02F;
  s.range_max_m = 10.0F;
  const float inf = std::numeric_limits<float>::infinity();
  s.ranges_m[0] = inf;
  s.ranges_m[1] = float(range);
  s.ranges_m[2] = inf;
  return s;
}

// The runner's own rules, without the protective fields on top (their tests are
// SafetyFieldsTest and the runner's field tests below): the rig's scans look through a slit.
MissionRunnerConfig without_fields() {
  MissionRunnerConfig c;
  c.fields.enabled = false;
  return c;
}

struct Rig {
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom;
  Topic<ObstacleField> obstacles{Footprint{0.25, 0.25}, 0.0, 0.0, 0.0, 0.3};
  Topic<MotionRequest> motion;
  RecordingSink sink;
  test::ScriptedMission mission;
  MissionRunnerConfig cfg = without_fields();
  MissionRunner runner{cfg, 0.01, 2, mission, frame, odom, obstacles, motion, sink};

  // One tick at time t [s] with the drives enabled or not.
  void tick(double t_s, bool drives = true) {
    SensorFrame& f = frame.edit();
    f.now_ns = hal::TimeNs(t_s * 1e9);
    f.wheels.count = 2;
    for (int i = 0; i < 2; ++i) {
      f.wheels.wheel[i].state = drives ? hal::DriveState::Enabled : hal::DriveState::Disabled;
    }
    frame.publish(f.now_ns);
    odom.publish(odom.get(), f.now_ns);
    runner.run();
  }
  // One tick at time t [s], drives enabled, of a test's own runner (configured otherwise).
  void run(MissionRunner& own, double t_s) {
    SensorFrame& f = frame.edit();
    f.now_ns = hal::TimeNs(t_s * 1e9);
    f.wheels.count = 2;
    for (int i = 0; i < 2; ++i) f.wheels.wheel[i].state = hal::DriveState::Enabled;
    frame.publish(f.now_ns);
    own.run();
  }
  // The odometry follows the last command for one 10 ms tick; then the scan `scan_at` makes at
  // the new pose goes into the obstacle field.
  template <typename ScanAt>
  const Pose2& follow_command(ScanAt scan_at) {
    Pose2& p = odom.edit().pose;
    const Twist& c = motion.get().twist;
    p.yaw = wrap_angle(p.yaw + c.wz * 0.01);
    p.x += c.vx * std::cos(p.yaw) * 0.01;
    p.y += c.vx * std::sin(p.yaw) * 0.01;
    odom.publish(0);
    obstacles.edit().update(scan_at(p), p);
    obstacles.publish(0);
    return p;
  }
  void obstacle_at(double range) {
    obstacles.edit().update(scan_with_point_ahead(range), Pose2{});
    obstacles.publish(0);
  }
};

TEST(MissionRunnerTest, EntersOnceThenUpdatesEveryTickWithItsContext) {
  Rig r;
  r.tick(0.5, false);
  r.tick(0.51, true);
  EXPECT_EQ(r.mission.enters, 1);
  EXPECT_DOUBLE_EQ(r.mission.enter_t_s, 0.5);
  ASSERT_EQ(r.mission.contexts.size(), 2U);
  EXPECT_DOUBLE_EQ(r.mission.contexts[0].t_s, 0.5);
  EXPECT_DOUBLE_EQ(r.mission.contexts[0].dt_s, 0.01);
  EXPECT_FALSE(r.mission.contexts[0].drives_ready);
  EXPECT_TRUE(r.mission.contexts[1].drives_ready);
  EXPECT_EQ(r.motion.seq(), 2U);  // a request every tick
}

TEST(MissionRunnerTest, PassesTheRequestedMotionThrough) {
  Rig r;
  r.mission.next.motion.twist = {0.3, 0.1, -0.2};
  r.tick(0.0);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.3);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vy, 0.1);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.wz, -0.2);
}

TEST(MissionRunnerTest, RaisesTheMissionsFaultWithTheStateItStruckIn) {
  Rig r;
  static const MissionState failed{MissionStatus::Failed, 9, "GAVE_UP", "stopped", false};
  r.mission.st = {MissionStatus::Active, 3, "WORKING", "busy", false};
  r.mission.next.fault = Fault::PathBlocked;
  r.mission.next_state = &failed;
  r.tick(0.0);
  ASSERT_EQ(r.sink.raised.size(), 1U);
  EXPECT_EQ(r.sink.raised[0].f, Fault::PathBlocked);
  EXPECT_EQ(r.sink.raised[0].in_state, "WORKING");  // not GAVE_UP: where it struck
}

TEST(MissionRunnerTest, SafeStopAfterAFaultExitsTheMissionOnceAndAsksNothingMore) {
  Rig r;
  r.mission.next.motion.twist = {0.5, 0.0, 0.0};
  r.tick(0.0);
  r.sink.fault = Fault::CameraTimeout;  // latched elsewhere
  r.mission.next.motion.twist = {0.5, 0.0, 0.0};
  for (int i = 1; i <= 5; ++i) r.tick(0.01 * i);
  EXPECT_EQ(r.mission.exits, 1);
  EXPECT_EQ(r.mission.contexts.size(), 1U);  // no update after the fault
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_EQ(r.motion.seq(), 6U);  // still publishing: zero
  EXPECT_TRUE(r.runner.telemetry().stopped);
}

TEST(MissionRunnerTest, StopsAGuardedMotionForAnObstacleAhead) {
  Rig r;
  r.obstacle_at(0.25 + 0.30);  // 0.30 m ahead of the bumper: inside stop_m (0.45)
  r.mission.next.motion = {{0.4, 0.0, 0.1}, true};
  r.tick(0.0);
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  EXPECT_EQ(r.runner.telemetry().obstacle_stops, 1U);
}

TEST(MissionRunnerTest, LeavesUnguardedOrClearMotionAlone) {
  Rig r;
  r.obstacle_at(0.25 + 0.30);
  r.mission.next.motion = {{0.4, 0.0, 0.0}, false};  // e.g. a bypass manoeuvre
  r.tick(0.0);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.4);
  Rig far;
  far.obstacle_at(0.25 + 0.60);  // beyond stop_m
  far.mission.next.motion = {{0.4, 0.0, 0.0}, true};
  far.tick(0.0);
  EXPECT_DOUBLE_EQ(far.motion.get().twist.vx, 0.4);
  EXPECT_EQ(r.runner.telemetry().obstacle_stops + far.runner.telemetry().obstacle_stops, 0U);
}

TEST(MissionRunnerTest, TheMissionAsksTheSameObstacleQuestion) {
  Rig r;
  r.mission.ask_obstacle = true;
  r.tick(0.0);  // no scan yet: nothing ahead
  r.obstacle_at(0.25 + 0.30);
  r.tick(0.01);
  r.obstacle_at(0.25 + 2.0);
  r.tick(0.02);
  EXPECT_EQ(r.mission.saw_obstacle, (std::vector<bool>{false, true, false}));
}

TEST(MissionRunnerTest, ConfigValidateNamesTheField) {
  MissionRunnerConfig c;
  EXPECT_TRUE(c.validate().is_ok());
  c.obstacle.stop_m = -1.0;
  const Status s = c.validate();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("runner.obstacle.stop_m: -1 m, expected 0.05 to 5 m"),
            std::string::npos)
      << s.message();
}

}  // namespace
}  // namespace carril::fw

namespace carril::fw {
namespace {

TEST(MissionRunnerTest, HoldsStillWithoutUpdatingWhileThePoseIsNotLocalised) {
  Rig r;
  Topic<OdometryMsg> pose;
  r.runner.watch_pose(pose);
  r.mission.next.motion.twist = {0.3, 0.0, 0.1};
  pose.edit().localised = false;
  pose.publish(0);
  r.tick(0.0);
  r.tick(0.01);
  EXPECT_TRUE(r.mission.contexts.empty());  // not asked while lost
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  EXPECT_EQ(r.runner.telemetry().unlocalised_ticks, 2U);
  pose.edit().localised = true;
  pose.publish(0);
  r.tick(0.02);
  EXPECT_EQ(r.mission.contexts.size(), 1U);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.3);
}

TEST(MissionRunnerTest, LostItTurnsInPlaceOnlyWithRoomToTurnAndPassesAJumpOnOnce) {
  Rig r;
  MissionRunnerConfig cfg;
  cfg.lost_turn_radps = 0.3;
  ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  MissionRunner runner{cfg, 0.01, 2, r.mission, r.frame, r.odom, r.obstacles, r.motion, r.sink};
  Topic<OdometryMsg> pose;
  runner.watch_pose(pose);
  auto tick = [&](double t_s) { r.run(runner, t_s); };
  r.mission.next.motion.twist = {0.3, 0.0, 0.0};
  pose.edit().localised = true;
  pose.publish(0);
  tick(0.0);  // entered, driving
  ASSERT_EQ(r.mission.enters, 1);
  pose.edit().localised = false;
  pose.publish(0);
  // No scan yet: it does not know there is room, so it stays still.
  tick(0.01);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  // The nearest return 0.5 m ahead of the centre: 0.25 m from the 0.5 x 0.5 m footprint, beyond
  // the 0.10 m its corners sweep plus the 0.05 m margin: it turns, without asking the mission.
  r.obstacle_at(0.5);
  tick(0.02);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.wz, 0.3);
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_EQ(r.mission.contexts.size(), 1U);
  // 0.38 m ahead: 0.13 m from the footprint, within 0.10 + 0.05: still.
  r.obstacle_at(0.38);
  tick(0.03);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  EXPECT_EQ(runner.telemetry().lost_turn_ticks, 1U);
  EXPECT_EQ(runner.telemetry().unlocalised_ticks, 3U);
  EXPECT_EQ(r.mission.relocalisations, 0);
  // Found again after a jump: the mission hears of it once, before its next update.
  pose.edit().localised = true;
  pose.edit().relocalisations = 1;
  pose.publish(0);
  tick(0.04);
  tick(0.05);
  EXPECT_EQ(r.mission.relocalisations, 1);
  EXPECT_EQ(runner.telemetry().relocalisations, 1U);
  EXPECT_EQ(r.mission.contexts.size(), 3U);
}

// Held unlocalised longer than max_unlocalised_s in a row, the runner gives up with the fault
// not_localised (a safe stop an operator sees); a spell localised in between starts the count
// again, and 0 waits for ever.
TEST(MissionRunnerTest, HeldUnlocalisedTooLongEndsInNotLocalised) {
  for (const double limit : {0.5, 0.0}) {
    Rig r;
    MissionRunnerConfig cfg;
    cfg.max_unlocalised_s = limit;
    ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
    MissionRunner runner{cfg, 0.01, 2, r.mission, r.frame, r.odom, r.obstacles, r.motion, r.sink};
    Topic<OdometryMsg> pose;
    runner.watch_pose(pose);
    auto tick = [&](int k, bool localised) {
      pose.edit().localised = localised;
      pose.publish(0);
      SensorFrame& f = r.frame.edit();
      f.now_ns = hal::TimeNs(k) * 10'000'000;
      f.wheels.count = 2;
      for (int i = 0; i < 2; ++i) f.wheels.wheel[i].state = hal::DriveState::Enabled;
      r.frame.publish(f.now_ns);
      runner.run();
    };
    r.mission.next.motion.twist = {0.3, 0.0, 0.0};
    int k = 0;
    // 0.4 s lost, 0.02 s localised, 0.4 s lost: never 0.5 s in a row.
    for (; k < 40; ++k) tick(k, false);
    tick(k++, true);
    tick(k++, true);
    for (int n = 0; n < 40; ++n) tick(k++, false);
    EXPECT_TRUE(r.sink.raised.empty()) << limit;
    // Then lost for good: the fault once past 0.5 s, and a still robot from then on.
    for (int n = 0; n < 100; ++n) tick(k++, false);
    if (limit > 0.0) {
      ASSERT_EQ(r.sink.raised.size(), 1U);
      EXPECT_EQ(r.sink.raised[0].f, Fault::NotLocalised);
      EXPECT_STREQ(fault_name(Fault::NotLocalised), "not_localised");
    } else {
      EXPECT_TRUE(r.sink.raised.empty());
    }
    EXPECT_EQ(r.motion.get().twist.vx, 0.0);
    EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  }
}

// A 180 deg lidar is blind behind: what it saw ahead before the robot turned away is still there
// for the corners a turn in place swings.
TEST(MissionRunnerTest, LostItDoesNotTurnOntoWhatItSawBeforeItsBlindSector) {
  Rig r;
  r.cfg.lost_turn_radps = 0.3;
  // What the field must remember: the corners' 0.104 m beyond the sides, the 0.05 m clearance
  // and 0.1 m of travel (the rig's field keeps 0.3 m); nothing without a lost turn.
  EXPECT_NEAR(r.cfg.lost_turn_reach_m(Footprint{0.25, 0.25}), std::sqrt(0.125) - 0.25 + 0.15,
              1e-12);
  EXPECT_EQ(MissionRunnerConfig{}.lost_turn_reach_m(Footprint{0.25, 0.25}), 0.0);
  MissionRunner runner{r.cfg, 0.01, 2, r.mission, r.frame, r.odom, r.obstacles, r.motion, r.sink};
  Topic<OdometryMsg> pose;
  runner.watch_pose(pose);
  auto tick = [&](double t_s) { r.run(runner, t_s); };
  pose.edit().localised = false;
  pose.publish(0);
  // 0.38 m ahead: 0.13 m from the footprint, within the 0.10 m its corners sweep plus 0.05.
  r.obstacle_at(0.38);
  tick(0.0);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  // Facing the other way (odometry turned half round), the scan shows nothing: the return is
  // behind, where no beam looks. It is remembered, so still no turn.
  r.odom.edit().pose = Pose2{0.0, 0.0, kPi};
  r.odom.publish(0);
  r.obstacles.edit().update(scan_with_point_ahead(std::numeric_limits<double>::infinity()),
                            Pose2{0.0, 0.0, kPi});
  r.obstacles.publish(0);
  tick(0.01);
  EXPECT_EQ(r.obstacles.get().clearance_m(Pose2{0.0, 0.0, kPi}), 1e9);
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  EXPECT_EQ(runner.telemetry().lost_turn_ticks, 0U);
  // Moved 0.5 m on, away from it (0.63 m from the footprint now): room to turn.
  r.odom.edit().pose = Pose2{-0.5, 0.0, kPi};
  r.odom.publish(0);
  r.obstacles.edit().update(scan_with_point_ahead(std::numeric_limits<double>::infinity()),
                            Pose2{-0.5, 0.0, kPi});
  r.obstacles.publish(0);
  tick(0.02);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.wz, 0.3);
}

// Still lost after a whole turn, the runner drives a leg toward open space (LostExplorer); found
// in the middle of it and lost again, it starts from a whole turn; and it stops a leg short of
// what the lidar shows ahead.
TEST(MissionRunnerTest, LostAfterAWholeTurnItDrivesALegAndStopsShortOfAnObstacle) {
  Rig r;
  r.cfg.lost_turn_radps = 0.3;
  r.cfg.lost_explore.speed_mps = 0.2;
  ASSERT_TRUE(r.cfg.validate().is_ok()) << r.cfg.validate().message();
  MissionRunner runner{r.cfg, 0.01, 2, r.mission, r.frame, r.odom, r.obstacles, r.motion, r.sink};
  Topic<OdometryMsg> pose;
  runner.watch_pose(pose);
  r.mission.next.motion.twist = {0.3, 0.0, 0.0};
  double t = 0.0;
  // One tick: the odometry follows the last command, the scan shows a return `range` ahead.
  auto tick = [&](bool localised, double range) {
    r.follow_command([range](const Pose2&) { return scan_with_point_ahead(range); });
    pose.edit().localised = localised;
    pose.publish(0);
    r.run(runner, t);
    t += 0.01;
  };
  // Lost: ticks until it drives; a whole turn at 0.3 rad/s is 2,094 ticks.
  auto ticks_to_a_leg = [&](double range) {
    int n = 0;
    do {
      tick(false, range);
      ++n;
    } while (r.motion.get().twist.vx == 0.0 && n < 4000);
    return n;
  };
  const double open = std::numeric_limits<double>::infinity();
  tick(true, open);  // entered
  int n = ticks_to_a_leg(open);
  EXPECT_GT(n, 2094);
  EXPECT_LT(n, 2200);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.2);
  for (int i = 0; i < 100; ++i) tick(false, open);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.2);
  EXPECT_EQ(runner.telemetry().lost_drive_ticks, 101U);
  EXPECT_EQ(runner.telemetry().lost_legs, 1U);
  // Found in the middle of the leg: the mission drives. Lost again: a whole turn first.
  tick(true, open);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.3);
  n = ticks_to_a_leg(open);
  EXPECT_GT(n, 2094);
  EXPECT_LT(n, 2200);
  // A return 0.8 m ahead of the centre: 0.55 m from the bumper, less than stop_free_m (0.6).
  EXPECT_EQ(runner.telemetry().lost_legs, 2U);
  const std::uint64_t driven = runner.telemetry().lost_drive_ticks;
  tick(false, 0.8);
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_EQ(runner.telemetry().lost_drive_ticks, driven);
}

// A room 1.8 m square round the start whose only way on is a corridor along +x, 0.7 m wide, that
// ends 1.5 m from the start: the leg toward it ends with the side walls 0.1 m from the body, no
// room to turn. The lidar: three beams, right, ahead and left, cast at these walls.
hal::LaserScan dead_end_scan(const Pose2& p) {
  struct Wall {
    double x0, y0, x1, y1;
  };
  static constexpr Wall kWalls[] = {{-0.9, -0.9, -0.9, 0.9},  {-0.9, 0.9, 0.5, 0.9},
                                    {-0.9, -0.9, 0.5, -0.9},  {0.5, 0.35, 0.5, 0.9},
                                    {0.5, -0.9, 0.5, -0.35},  {0.5, 0.35, 1.5, 0.35},
                                    {0.5, -0.35, 1.5, -0.35}, {1.5, -0.35, 1.5, 0.35}};
  hal::LaserScan s;
  s.seq = 1;
  s.count = 3;
  s.angle_min_rad = float(-kPi / 2);
  s.angle_increment_rad = float(kPi / 2);
  s.range_min_m = 0.02F;
  s.range_max_m = 10.0F;
  for (int b = 0; b < 3; ++b) {
    const double a = p.yaw - kPi / 2 + b * kPi / 2, dx = std::cos(a), dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const Wall& w : kWalls) {
      // p + t d = w0 + u (w1 - w0), t > 0, u in [0, 1].
      const double ex = w.x1 - w.x0, ey = w.y1 - w.y0, den = dx * ey - dy * ex;
      if (std::fabs(den) < 1e-12) continue;
      const double qx = w.x0 - p.x, qy = w.y0 - p.y;
      const double t = (qx * ey - qy * ex) / den, u = (qx * dy - qy * dx) / den;
      if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::fmin(best, t);
    }
    s.ranges_m[std::size_t(b)] = float(best);
  }
  return s;
}

// Lost, the leg toward the corridor ends with no room to turn: the runner hands the explorer what
// is behind, and the robot backs to where the leg began and looks round again from there.
TEST(MissionRunnerTest, LostInADeadEndItBacksToWhereTheLegBegan) {
  Rig r;
  r.cfg.lost_turn_radps = 0.3;
  r.cfg.lost_explore.speed_mps = 0.2;
  MissionRunner runner{r.cfg, 0.01, 2, r.mission, r.frame, r.odom, r.obstacles, r.motion, r.sink};
  Topic<OdometryMsg> pose;
  runner.watch_pose(pose);
  pose.edit().localised = false;
  pose.publish(0);
  r.odom.edit().pose = Pose2{0.0, 0.0, 0.5};
  double t = 0.0, max_x = 0.0;
  bool backed = false;
  for (int i = 0; i < 6000 && !(backed && r.motion.get().twist.wz > 0.0); ++i) {
    const Pose2& p = r.follow_command(dead_end_scan);
    r.run(runner, t);
    t += 0.01;
    max_x = std::fmax(max_x, p.x);
    backed = backed || r.motion.get().twist.vx < 0.0;
  }
  // The leg ended 0.6 m short of the end wall (from the bumper), 0.65 m from the start.
  EXPECT_NEAR(max_x, 0.65, 0.01);
  EXPECT_EQ(runner.telemetry().lost_legs, 1U);
  EXPECT_EQ(runner.telemetry().lost_backs, 1U);
  // Backed to the start, and turning there again.
  const Pose2& p = r.odom.get().pose;
  EXPECT_NEAR(std::hypot(p.x, p.y), 0.0, 0.03);
  EXPECT_DOUBLE_EQ(r.motion.get().twist.wz, 0.3);
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
}

}  // namespace
}  // namespace carril::fw
