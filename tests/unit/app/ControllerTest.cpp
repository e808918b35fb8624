// Controller: runs the target's task table at the declared rates, latches the first fault (safe
// stop whatever the tasks left, counted, logged with the state it struck in), logs the mission's
// phase and state changes, counts what the event log drops and reports task overruns.
#include "firmware/app/Controller.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "firmware/app/EventFormat.hpp"
#include "firmware/mission/MissionRunner.hpp"
#include "tests/unit/mission/ScriptedMission.hpp"

namespace carril::fw {
namespace {

class FakeClock final : public hal::Clock {
 public:
  hal::TimeNs now_ns() const override { return 0; }
  hal::TimeNs cpu_now_ns() const override { return cpu_ns; }
  void sleep_until_ns(hal::TimeNs) override {}
  hal::TimeNs cpu_ns = 0;
};

struct Rig {
  FakeClock clock;
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom;
  Topic<ObstacleField> obstacles{Footprint{}, 0.0, 0.0, 0.0};
  Topic<MotionRequest> motion;
  Topic<ActuatorCommand> command;
  test::ScriptedMission mission;
  Controller ctl;
  MissionRunner runner;
  std::vector<std::string> ran;  // task names, in the order they ran
  hal::TimeNs burn_ns = 0;       // compute time the "slow" task takes

  explicit Rig(double rate_hz = 100.0)
      : ctl(clock, rate_hz, frame, command, runner),
        runner(MissionRunnerConfig{}, 0.01, 2, mission, frame, odom, obstacles, motion, ctl) {}

  std::vector<Fault> to_raise;  // raised by the fast task on the next tick (a health check)
  bool overfill = false;        // the fast task pushes onto a full StaticVector (a bug)
  void fast() {
    ran.emplace_back("fast");
    if (overfill) {
      StaticVector<int, 1> v;
      v.push_back(1);
      EXPECT_FALSE(v.push_back(2));  // refused: nothing written past the storage
      EXPECT_EQ(v.size(), 1U);
      overfill = false;
    }
    for (Fault f : to_raise) ctl.raise(f);
    to_raise.clear();
  }
  void slow() {
    ran.emplace_back("slow");
    clock.cpu_ns += burn_ns;
  }
  // What a motion stage would leave: run with wheel setpoints.
  void drive() {
    ran.emplace_back("drive");
    ActuatorCommand& c = command.edit();
    c.drive = DriveRequest::Run;
    c.wheel_count = 2;
    c.wheel_radps = {3.0F, 3.0F};
    c.twist = {0.4, 0.0, 0.0};
    command.publish(frame.get().now_ns);
  }
  void mission_task() {
    ran.emplace_back("mission");
    runner.run();
  }

  Status declare() {
    const TaskSpec table[] = {
        TaskSpec::bind<&Rig::fast>("fast", 100.0, 0, 1000, this),
        TaskSpec::bind<&Rig::slow>("slow", 25.0, 2, 1000, this),
        TaskSpec::bind<&Rig::mission_task>("mission", 100.0, 0, 1000, this),
        TaskSpec::bind<&Rig::drive>("drive", 100.0, 0, 1000, this),
    };
    for (const TaskSpec& t : table) {
      if (Status s = ctl.add_task(t); !s) return s;
    }
    return ctl.check();
  }
  ActuatorCommand tick(int i) {
    SensorFrame f;
    f.now_ns = hal::TimeNs(i) * 10'000'000;
    return ctl.tick(f);
  }
  std::vector<std::string> events() {
    std::vector<std::string> out;
    Event e;
    while (ctl.events().pop(e)) {
      char buf[200];
      format_event(e, double(e.t_ns) * 1e-9, buf, sizeof buf);
      out.emplace_back(buf);
    }
    return out;
  }
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ControllerTest, RunsTheDeclaredTableInOrderAtItsRates) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  for (int i = 0; i < 8; ++i) r.tick(i);
  // 25 Hz on a 100 Hz tick: every 4th tick, on offset 2.
  const std::vector<std::string> want = {
      "fast",  "mission", "drive",   "fast",    "mission", "drive",   "fast",    "slow", "mission",
      "drive", "fast",    "mission", "drive",   "fast",    "mission", "drive",   "fast", "mission",
      "drive", "fast",    "slow",    "mission", "drive",   "fast",    "mission", "drive"};
  EXPECT_EQ(r.ran, want);
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.ticks, 8U);
  ASSERT_EQ(t.tasks.size(), 4U);
  EXPECT_EQ(t.tasks[1].divisor, 4U);
  EXPECT_EQ(t.tasks[1].runs, 2U);
}

TEST(ControllerTest, AnEmptyTableOrABadTaskIsAnErrorNamingIt) {
  Rig r;
  EXPECT_FALSE(r.ctl.check().is_ok());
  EXPECT_TRUE(contains(r.ctl.check().message(), "no task")) << r.ctl.check().message();
  const Status s = r.ctl.add_task(TaskSpec::bind<&Rig::fast>("camera", 0.0, 0, 1000, &r));
  ASSERT_FALSE(s.is_ok());
  EXPECT_TRUE(contains(s.message(), "camera")) << s.message();
  EXPECT_TRUE(contains(s.message(), "rate")) << s.message();
  const Status off = r.ctl.add_task(TaskSpec::bind<&Rig::fast>("lidar", 20.0, 5, 1000, &r));
  ASSERT_FALSE(off.is_ok());
  EXPECT_TRUE(contains(off.message(), "lidar")) << off.message();
  EXPECT_TRUE(contains(off.message(), "offset")) << off.message();
}

TEST(ControllerTest, ABadTickRateIsAnErrorAtInitNotACrash) {
  for (const double rate : {0.0, -5.0, std::numeric_limits<double>::quiet_NaN()}) {
    Rig r(rate);
    EXPECT_FALSE(r.ctl.check().is_ok()) << rate;
    EXPECT_FALSE(r.declare().is_ok()) << rate;
  }
}

TEST(ControllerTest, TheFirstFaultLatchesIsCountedOnceAndQuickStops) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  r.mission.st = {MissionStatus::Active, 2, "WORKING", "busy", true};
  EXPECT_EQ(r.tick(0).drive, DriveRequest::Run);
  r.to_raise = {Fault::ScannerBlind, Fault::CameraTimeout};  // later ones are ignored
  for (int i = 1; i < 4; ++i) {
    const ActuatorCommand c = r.tick(i);  // the drive task still leaves Run behind
    EXPECT_EQ(c.drive, DriveRequest::QuickStop);
    EXPECT_EQ(c.wheel_radps[0], 0.0F);
    EXPECT_EQ(c.twist.vx, 0.0);
  }
  EXPECT_STREQ(r.ctl.state_name(), "FAULT");
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.fault, Fault::ScannerBlind);
  EXPECT_EQ(t.fault_counts[std::size_t(Fault::ScannerBlind)], 1U);
  EXPECT_EQ(t.fault_counts[std::size_t(Fault::CameraTimeout)], 0U);
  EXPECT_EQ(t.status, MissionStatus::Failed);
  const std::vector<std::string> ev = r.events();
  ASSERT_GE(ev.size(), 2U);
  EXPECT_TRUE(contains(ev[0], "FAULT scanner_blind (code 0x0000) in WORKING: safe stop")) << ev[0];
  EXPECT_TRUE(contains(ev[1], "WORKING -> FAULT")) << ev[1];
  EXPECT_EQ(r.mission.exits, 1);  // the runner stopped the mission
}

TEST(ControllerTest, AFailedCheckInATaskLatchesCheckFailedAndQuickStops) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  r.mission.st = {MissionStatus::Active, 2, "WORKING", "busy", true};
  EXPECT_EQ(r.tick(0).drive, DriveRequest::Run);
  const std::uint32_t before = check_failures().count;
  r.overfill = true;
  const ActuatorCommand c = r.tick(1);
  EXPECT_EQ(c.drive, DriveRequest::QuickStop);  // the same tick
  EXPECT_EQ(c.wheel_radps[0], 0.0F);
  EXPECT_EQ(r.tick(2).drive, DriveRequest::QuickStop);
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.fault, Fault::CheckFailed);
  EXPECT_EQ(t.fault_counts[std::size_t(Fault::CheckFailed)], 1U);
  EXPECT_EQ(t.checks_failed, before + 1);
  const std::vector<std::string> ev = r.events();
  ASSERT_GE(ev.size(), 1U);
  EXPECT_TRUE(contains(ev[0], "FAULT check_failed (code 0x")) << ev[0];
  EXPECT_EQ(r.mission.exits, 1);
  // A controller made after the failure starts clear: the count it saw at init is not its own.
  Rig later;
  ASSERT_TRUE(later.declare().is_ok());
  later.mission.st = {MissionStatus::Active, 2, "WORKING", "busy", true};
  EXPECT_EQ(later.tick(0).drive, DriveRequest::Run);
}

TEST(ControllerTest, LogsPhaseThenStateChangesOfTheMission) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  static const MissionState working{MissionStatus::Active, 1, "WORKING", "busy", true};
  r.tick(0);
  r.mission.next_state = &working;
  r.mission.next_phase = "busy";
  r.tick(1);
  r.tick(2);  // nothing new
  const std::vector<std::string> ev = r.events();
  ASSERT_EQ(ev.size(), 2U);
  EXPECT_TRUE(contains(ev[0], "WORKING: busy")) << ev[0];
  EXPECT_TRUE(contains(ev[1], "WAIT -> WORKING")) << ev[1];
  EXPECT_STREQ(r.ctl.state_name(), "WORKING");
}

TEST(ControllerTest, TheEventLogCountsWhatItDrops) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  for (std::size_t i = 0; i < Controller::kEventLog + 5; ++i) {
    static const MissionState a{MissionStatus::Active, 1, "A", "", false};
    static const MissionState b{MissionStatus::Active, 2, "B", "", false};
    r.mission.next_state = i % 2 == 0 ? &a : &b;
    r.tick(int(i) * 10);  // one change every 0.1 s: under kEventsPerSecond, none throttled
  }
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.events_dropped, 5U);
  EXPECT_EQ(t.events_throttled, 0U);
  EXPECT_EQ(r.events().size(), Controller::kEventLog);
}

TEST(ControllerTest, AFloodOfEventsIsThrottledAndTheFirstFaultIsKeptApart) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  static const MissionState a{MissionStatus::Active, 1, "A", "", false};
  static const MissionState b{MissionStatus::Active, 2, "B", "", false};
  int i = 0;
  for (; i < 100; ++i) {  // 1 s flapping between two states: 100 changes
    r.mission.next_state = i % 2 == 0 ? &a : &b;
    r.tick(i);
  }
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.events_throttled, 100U - Controller::kEventsPerSecond);
  EXPECT_FALSE(t.has_first_fault);
  r.to_raise = {Fault::ScannerBlind};
  r.tick(i++);
  r.burn_ns = 5000;  // then 100 s of the slow task overrunning: one event a second
  for (; i < 10'100; ++i) r.tick(i);
  r.ctl.fill_telemetry(t);
  ASSERT_TRUE(t.has_first_fault);
  EXPECT_EQ(t.first_fault.fault, Fault::ScannerBlind);
  EXPECT_EQ(t.first_fault.t_ns, hal::TimeNs(100) * 10'000'000);
  ASSERT_NE(r.ctl.first_fault(), nullptr);
  char line[200];
  format_event(*r.ctl.first_fault(), 1.0, line, sizeof line);
  EXPECT_TRUE(contains(line, "FAULT scanner_blind (code 0x0000) in ")) << line;
  // The log itself has long overwritten it: only the copy kept apart survives the flood.
  bool in_log = false;
  for (const std::string& e : r.events()) in_log = in_log || contains(e, "scanner_blind");
  EXPECT_FALSE(in_log);
  EXPECT_GT(t.events_dropped, 0U);
}

TEST(ControllerTest, TaskOverrunsBecomeThrottledEvents) {
  Rig r;
  ASSERT_TRUE(r.declare().is_ok());
  r.burn_ns = 5000;  // 5 us against a 1 us budget, every time the slow task runs
  for (int i = 0; i < 100; ++i) r.tick(i);  // 1 s: 25 overruns
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.tasks[1].overruns, 25U);
  std::vector<std::string> overruns;
  for (const std::string& e : r.events()) {
    if (contains(e, "overran")) overruns.push_back(e);
  }
  ASSERT_EQ(overruns.size(), 1U);  // throttled: one event for the first second
  EXPECT_TRUE(contains(overruns[0], "warning: task slow overran its 1 us budget")) << overruns[0];
}

TEST(ControllerTest, ATickOverItsBudgetIsCounted) {
  Rig r(100.0);
  ASSERT_TRUE(r.declare().is_ok());
  r.burn_ns = 6'000'000;  // 6 ms > half of the 10 ms period
  for (int i = 0; i < 8; ++i) r.tick(i);
  ControllerTelemetry t;
  r.ctl.fill_telemetry(t);
  EXPECT_EQ(t.tick_overruns, 2U);  // the two ticks the slow task ran on
  EXPECT_DOUBLE_EQ(t.tick_budget_us, 5000.0);
}

TEST(ControllerTest, ConsecutiveOverrunsBeyondTheLimitSafeStop) {
  Rig r(100.0);
  ASSERT_TRUE(r.declare().is_ok());
  r.ctl.set_overrun_limit(3);
  // Isolated overruns (the slow task on every 4th tick) never make 3 in a row.
  r.burn_ns = 6'000'000;
  for (int i = 0; i < 40; ++i) EXPECT_EQ(r.tick(i).drive, DriveRequest::Run) << i;
  EXPECT_EQ(r.ctl.fault(), Fault::None);
  // Missed deadlines count too: the next two ticks miss theirs, and the slow one overruns.
  r.ctl.missed_deadline();
  EXPECT_EQ(r.tick(40).drive, DriveRequest::Run);  // 40 % 4 = 0: slow does not run; missed
  r.ctl.missed_deadline();
  EXPECT_EQ(r.tick(41).drive, DriveRequest::Run);  // missed again: 2 in a row
  const ActuatorCommand c = r.tick(42);            // the slow task's tick: the third
  EXPECT_EQ(c.drive, DriveRequest::QuickStop);
  EXPECT_EQ(r.ctl.fault(), Fault::TickOverrun);
  bool logged = false;
  for (const std::string& e : r.events()) logged = logged || contains(e, "tick_overrun");
  EXPECT_TRUE(logged);
}

TEST(ControllerTest, NoOverrunLimitByDefault) {
  Rig r(100.0);
  ASSERT_TRUE(r.declare().is_ok());
  r.burn_ns = 6'000'000;
  for (int i = 0; i < 10; ++i) r.ctl.missed_deadline(), r.tick(i);
  EXPECT_EQ(r.ctl.fault(), Fault::None);
}

}  // namespace
}  // namespace carril::fw
