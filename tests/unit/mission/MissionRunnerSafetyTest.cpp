// The runner's safety rules over whole minutes of ticks: every request through the protective
// fields and the swept-footprint check (stopped, it resumes by itself; stopped too long, it
// faults motion_blocked), and the stall watch (no progress while not waiting: stalled).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "firmware/mission/MissionRunner.hpp"
#include "tests/unit/mission/ScriptedMission.hpp"
#include "tests/unit/perception/ScanScene.hpp"

namespace carril::fw {
namespace {

struct Sink final : FaultSink {
  void raise(Fault f, std::uint16_t, const char*) override {
    raised.push_back(f);
    if (fault == Fault::None) fault = f;
  }
  bool latched() const override { return fault != Fault::None; }
  std::vector<Fault> raised;
  Fault fault = Fault::None;
};

const Footprint kBody{0.25, 0.2};

struct Rig {
  explicit Rig(MissionRunnerConfig c = {}) : cfg(c) {}
  MissionRunnerConfig cfg;
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom;
  Topic<ObstacleField> obstacles{kBody, 0.0, 0.0, 0.0};
  Topic<MotionRequest> motion;
  Sink sink;
  test::ScriptedMission mission;
  MissionRunner runner{cfg, 0.01, 2, mission, frame, odom, obstacles, motion, sink};
  double t = 0.0;

  // A 360 deg scan of `scene` from the robot's pose.
  void see(const test::ScanScene& scene) {
    auto s = scene.scan(odom.get().pose, Pose2{}, 1441, 2.0 * kPi);
    obstacles.edit().update(*s, odom.get().pose);
    obstacles.publish(0);
  }
  // One 10 ms tick; the robot moves by `step` [m] along x when `moves`.
  void tick(double step = 0.0) {
    SensorFrame& f = frame.edit();
    f.now_ns = hal::TimeNs(t * 1e9);
    f.wheels.count = 2;
    for (int i = 0; i < 2; ++i) f.wheels.wheel[i].state = hal::DriveState::Enabled;
    frame.publish(f.now_ns);
    odom.edit().pose.x += step;
    odom.publish(f.now_ns);
    runner.run();
    t += 0.01;
  }
  bool raised(Fault f) const {
    for (Fault g : sink.raised) {
      if (g == f) return true;
    }
    return false;
  }
};

TEST(MissionRunnerSafetyTest, TurningOnTheSpotForEverIsAStall) {
  Rig r;
  r.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  r.mission.next.motion.twist = {0.0, 0.0, 0.6};  // a robot at a fork, turning and turning
  for (int i = 0; i < 5990; ++i) r.tick();  // 59.9 s
  EXPECT_TRUE(r.sink.raised.empty());
  for (int i = 0; i < 20; ++i) r.tick();
  ASSERT_EQ(r.sink.raised.size(), 1U);
  EXPECT_EQ(r.sink.raised[0], Fault::Stalled);
  EXPECT_STREQ(fault_name(Fault::Stalled), "stalled");
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
}

TEST(MissionRunnerSafetyTest, ProgressWaitingOrBeingDoneIsNoStall) {
  Rig moving;
  moving.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  moving.mission.next.motion.twist = {0.5, 0.0, 0.0};
  for (int i = 0; i < 12000; ++i) moving.tick(0.005);  // 0.5 m/s for two minutes
  EXPECT_TRUE(moving.sink.raised.empty());

  Rig waiting;
  waiting.mission.st = {MissionStatus::Starting, 0, "START", "wait", false, true};
  for (int i = 0; i < 12000; ++i) waiting.tick();
  EXPECT_TRUE(waiting.sink.raised.empty());

  Rig done;
  done.mission.st = {MissionStatus::Done, 4, "END", "stopped", false};
  for (int i = 0; i < 12000; ++i) done.tick();
  EXPECT_TRUE(done.sink.raised.empty());

  // Creeping 1 mm a tick (0.1 m/s) is progress; back and forth within 0.2 m is not.
  Rig creeping;
  creeping.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  for (int i = 0; i < 12000; ++i) creeping.tick(0.001);
  EXPECT_TRUE(creeping.sink.raised.empty());
  Rig rocking;
  rocking.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  for (int i = 0; i < 12000; ++i) rocking.tick((i / 100) % 2 == 0 ? 0.002 : -0.002);
  EXPECT_TRUE(rocking.raised(Fault::Stalled));
}

TEST(MissionRunnerSafetyTest, AStopByTheFieldsResumesByItselfAndFaultsWhenItLasts) {
  Rig r;
  r.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  r.mission.next.motion.twist = {0.4, 0.0, 0.0};
  test::ScanScene box;
  box.segments.push_back({Vec2(0.25 + 0.02, -0.3), Vec2(0.25 + 0.02, 0.3)});  // 2 cm ahead
  r.see(box);
  r.tick();
  EXPECT_EQ(r.motion.get().twist.vx, 0.0);
  EXPECT_GT(r.runner.telemetry().field_stops, 0U);
  // Cleared (the box was carried away): the request goes through again.
  r.see(test::ScanScene{});
  r.tick();
  EXPECT_DOUBLE_EQ(r.motion.get().twist.vx, 0.4);
  // Back, and staying: stopped for 30 s in a row, then motion_blocked.
  r.see(box);
  for (int i = 0; i < 2990; ++i) r.tick();
  EXPECT_TRUE(r.sink.raised.empty());
  for (int i = 0; i < 20; ++i) r.tick();
  ASSERT_EQ(r.sink.raised.size(), 1U);
  EXPECT_EQ(r.sink.raised[0], Fault::MotionBlocked);
  EXPECT_GE(r.runner.telemetry().blocked_max_s, 30.0);
}

TEST(MissionRunnerSafetyTest, ATurnOnTheSpotIsStoppedWhenItsCornersWouldMeetSomething) {
  Rig r;
  r.mission.st = {MissionStatus::Active, 1, "FOLLOW", "track", true};
  r.mission.next.motion.twist = {0.0, 0.0, 1.0};
  // A post just off the front-left corner, beyond the side: the corners' circle (0.32 m) meets it.
  test::ScanScene post;
  post.discs.push_back({Vec2(0.2, 0.27), 0.02});
  r.see(post);
  r.tick();
  EXPECT_EQ(r.motion.get().twist.wz, 0.0);
  EXPECT_STREQ(r.runner.telemetry().last_stop, "turn");
  // The same post 0.4 m off: the turn goes through.
  Rig far;
  far.mission.st = r.mission.st;
  far.mission.next.motion.twist = {0.0, 0.0, 1.0};
  test::ScanScene away;
  away.discs.push_back({Vec2(0.2, 0.6), 0.02});
  far.see(away);
  far.tick();
  EXPECT_DOUBLE_EQ(far.motion.get().twist.wz, 1.0);
}

TEST(MissionRunnerSafetyTest, ConfigValidateNamesTheNewFields) {
  MissionRunnerConfig c;
  c.blocked_timeout_s = 0.0;
  EXPECT_NE(std::string(c.validate().message())
                .find("runner.blocked_timeout_s: 0 s, expected 0.1 to 86400 s"),
            std::string::npos);
  c = {};
  c.check.pad_m = 2.0;
  EXPECT_NE(std::string(c.validate().message()).find("runner.check.pad_m: 2 m, expected 0 to 0.5 m"),
            std::string::npos);
}

}  // namespace
}  // namespace carril::fw
