// The CANopen master (hal/canopen/CanopenWheelDrives) against the drive emulator
// (host_sim/drives/DriveEmulator) on the loopback bus: both sides of docs/can-protocol.md, written
// separately, must agree. Four drives as on a Campero, 100 Hz control, the fault reactions of
// issue 9 item 7 with each one's outcome and time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"
#include "host_sim/drives/DriveEmulator.hpp"

namespace carril::sim {
namespace {

using hal::TimeNs;
using hal::canopen::CanopenConfig;
using hal::canopen::CanopenWheelDrives;
using State = hal::cia402::State;
constexpr TimeNs kMs = 1'000'000;
constexpr int kWheels = 4;
constexpr TimeNs kHeartbeatNs = 50 * kMs;  // the drives' heartbeat period

class FakeClock final : public hal::Clock {
 public:
  TimeNs now_ns() const override { return t; }
  TimeNs cpu_now_ns() const override { return t; }
  void sleep_until_ns(TimeNs until) override { t = std::max(t, until); }
  TimeNs t = 0;
};

// The master on endpoint 0, drives 1..4 on endpoints 1..4; time moves in 1 ms physics steps.
class Rig : public hal::canopen::BringUpWaiter {
 public:
  static CanopenConfig config() {
    CanopenConfig c;
    c.wheels = kWheels;
    for (int i = 0; i < kWheels; ++i) {
      c.drive[i].node = static_cast<std::uint8_t>(1 + i);
      c.drive[i].units = hal::cia402::DriveUnits{4096.0, 12.52};
      c.drive[i].heartbeat_ms = 50;
      c.drive[i].master_node = 127;
      c.drive[i].master_timeout_ms = 150;
    }
    c.master_node = 127;
    c.master_heartbeat_ns = 50 * kMs;
    c.control_period_ns = 10 * kMs;
    c.heartbeat_consumer_ns = 120 * kMs;
    c.sdo_timeout_ns = 100 * kMs;
    c.boot_timeout_ns = 2000 * kMs;
    c.enable_timeout_ns = 1000 * kMs;
    return c;
  }

  explicit Rig(const CanopenConfig& cfg = config()) : bus_(bus_config()), cfg_(cfg) {
    for (int i = 0; i < kWheels; ++i) {
      DriveEmulator::Config e;
      e.node = cfg.drive[i].node;
      e.units = cfg.drive[i].units;
      drive_[i] = std::make_unique<DriveEmulator>(bus_.endpoint(1 + i), e);
    }
    master_ = std::make_unique<CanopenWheelDrives>(bus_.endpoint(0), clock_, *this, cfg_);
  }

  // BringUpWaiter: the world runs while the master waits.
  void wait(TimeNs until) override {
    while (clock_.t < until) physics();
  }
  // One 1 ms physics step: the wire, then every drive.
  void physics() {
    clock_.t += kMs;
    bus_.transfer();
    for (auto& d : drive_) d->step(clock_.t, 1e-3);
    bus_.transfer();
  }
  // One 10 ms control period: the master's sync (if it is alive), then the world for 10 ms.
  void period(bool master_alive = true) {
    if (master_alive) master_->sync();
    for (int k = 0; k < 10; ++k) physics();
  }
  bool up_and_enabled() {
    const hal::DriveInitResult r = master_->init();
    if (!r.ok) {
      ADD_FAILURE() << r.what;
      return false;
    }
    master_->enable();
    for (int k = 0; k < 50; ++k) {
      period();
      if (all_enabled()) return true;
    }
    return false;
  }
  bool all_enabled() const {
    hal::WheelFeedbackSet fb;
    master_->read(fb);
    for (int i = 0; i < kWheels; ++i) {
      if (fb.wheel[std::size_t(i)].state != hal::DriveState::Enabled) return false;
    }
    return true;
  }
  void drive_at(float radps) {
    const float sp[kWheels] = {radps, radps, radps, radps};
    master_->set_velocity(sp, kWheels);
  }
  // The largest wheel speed any drive's motor produces [rad/s].
  double max_wheel_speed() const {
    double m = 0.0;
    for (const auto& d : drive_) m = std::max(m, std::fabs(d->wheel_speed_radps()));
    return m;
  }
  hal::WheelFeedback feedback(int i) const {
    hal::WheelFeedbackSet fb;
    master_->read(fb);
    return fb.wheel[std::size_t(i)];
  }

  CanopenWheelDrives& master() { return *master_; }
  DriveEmulator& drive(int i) { return *drive_[i]; }
  FakeClock& clock() { return clock_; }

 private:
  static hal::LoopbackCanBus::Config bus_config() {
    hal::LoopbackCanBus::Config c;
    c.endpoints = 1 + kWheels;
    c.tx_depth = 128;
    c.rx_depth = 256;
    return c;
  }
  hal::LoopbackCanBus bus_;
  FakeClock clock_;
  CanopenConfig cfg_;
  std::unique_ptr<DriveEmulator> drive_[kWheels];
  std::unique_ptr<CanopenWheelDrives> master_;
};

TEST(MasterAgainstEmulator, BringsFourDrivesUpAndTheyFollowTheSetpoints) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  for (int i = 0; i < kWheels; ++i) {
    EXPECT_EQ(r.drive(i).state(), State::OperationEnabled);
    EXPECT_EQ(r.drive(i).nmt_state(), hal::canopen::NmtState::Operational);
    EXPECT_EQ(r.drive(i).od().get(0x6060, 0), 3U) << "profile velocity mode";
    EXPECT_EQ(r.drive(i).counters().sdo_aborts_sent, 0U);
  }
  r.drive_at(4.0F);
  for (int k = 0; k < 100; ++k) r.period();  // 1 s: 4 rad/s at 25 rad/s^2 takes 0.16 s
  for (int i = 0; i < kWheels; ++i) {
    EXPECT_NEAR(r.drive(i).wheel_speed_radps(), 4.0, 0.01) << i;
    EXPECT_NEAR(r.feedback(i).velocity_radps, 4.0, 0.01) << i;
    EXPECT_EQ(r.feedback(i).fault, hal::DriveFault::None);
  }
  // Odometry comes from position actual: what the motor turned, as sampled at the SYNC the
  // feedback is stamped with (the drive kept turning at 4 rad/s since).
  for (int i = 0; i < kWheels; ++i) {
    const hal::WheelFeedback f = r.feedback(i);
    const double since_s = double(r.clock().t - f.stamp_ns) * 1e-9;
    EXPECT_LE(since_s, 0.0201) << "feedback at most two periods old";
    EXPECT_NEAR(f.position_rad, r.drive(i).wheel_position_rad() - 4.0 * since_s, 0.005) << i;
  }
  EXPECT_GT(r.feedback(0).position_rad, 3.3);  // about 4 rad/s for 1 s, less the ramp
  EXPECT_EQ(r.master().counters().faults, 0U);
  EXPECT_EQ(r.master().counters().malformed, 0U);
}

TEST(MasterAgainstEmulator, ALostDriveHeartbeatStopsEveryWheelWithinThreePeriods) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  r.drive_at(4.0F);
  for (int k = 0; k < 60; ++k) r.period();
  const TimeNs silent_at = r.clock().t;
  r.drive(2).set_silence(DriveEmulator::Silence::Heartbeat);
  TimeNs fault_at = -1, stopped_at = -1;
  bool all_braking = false;  // at the fault, every drive had left Operation enabled
  for (int k = 0; k < 100 && stopped_at < 0; ++k) {
    r.period();
    if (fault_at < 0 && r.feedback(2).state == hal::DriveState::Fault) {
      fault_at = r.clock().t;
      all_braking = true;
      for (int i = 0; i < kWheels; ++i) {
        all_braking = all_braking && r.drive(i).state() != State::OperationEnabled;
      }
    }
    if (fault_at >= 0 && r.max_wheel_speed() < 0.01) stopped_at = r.clock().t;
  }
  ASSERT_GE(fault_at, 0) << "no fault for the silent drive";
  ASSERT_GE(stopped_at, 0) << "the wheels did not stop";
  std::printf(
      "heartbeat silence: drive fault after %.0f ms, every wheel < 0.01 rad/s after %.0f "
      "ms (3 heartbeat periods = 150 ms)\n",
      double(fault_at - silent_at) / 1e6, double(stopped_at - silent_at) / 1e6);
  // The last heartbeat came at most one period before the silence began: FAULT and every wheel
  // braking (quick stop) within 3 heartbeat periods of it; standing still once the 50 rad/s^2
  // quick-stop ramp (80 ms from 4 rad/s) and the velocity loop's lag (5 x 20 ms) have run.
  EXPECT_LE(fault_at - silent_at, 3 * kHeartbeatNs);
  EXPECT_TRUE(all_braking);
  EXPECT_LE(stopped_at - fault_at, 200 * kMs);
  EXPECT_EQ(static_cast<std::uint16_t>(r.feedback(2).fault), 0x8130);
  EXPECT_NE(std::string(r.master().last_fault()).find("node 3"), std::string::npos)
      << r.master().last_fault();
  EXPECT_EQ(r.master().counters().heartbeat_losses, 1U);
}

TEST(MasterAgainstEmulator, AnEmcyFaultIsReportedWithItsCodeAndEveryWheelStops) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  r.drive_at(3.0F);
  for (int k = 0; k < 40; ++k) r.period();
  r.drive(1).inject_fault(0x2310);
  for (int k = 0; k < 60; ++k) r.period();
  EXPECT_EQ(r.feedback(1).state, hal::DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(r.feedback(1).fault), 0x2310);
  EXPECT_EQ(r.master().last_emcy_code(1), 0x2310);
  const std::string why = r.master().last_fault();
  EXPECT_NE(why.find("0x2310"), std::string::npos) << why;
  EXPECT_NE(why.find("over-current"), std::string::npos) << why;
  EXPECT_LT(r.max_wheel_speed(), 0.01);
}

TEST(MasterAgainstEmulator, AFaultGetsOneResetThenStaysStopped) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  r.drive(0).inject_fault(0x3220, /*persistent=*/true);  // under-voltage that does not clear
  for (int k = 0; k < 20; ++k) r.period();
  ASSERT_EQ(r.feedback(0).state, hal::DriveState::Fault);
  r.master().reset_faults();
  r.master().enable();
  for (int k = 0; k < 150; ++k) r.period();
  EXPECT_EQ(r.drive(0).state(), State::Fault);
  EXPECT_EQ(r.master().counters().fault_resets, 1U) << "one attempt, no reset loop";
  EXPECT_LT(r.max_wheel_speed(), 0.01);
  // Once the cause is gone, a new reset_faults() brings it back.
  r.drive(0).clear_persistent_fault();
  r.master().reset_faults();
  r.master().enable();
  for (int k = 0; k < 100 && !r.all_enabled(); ++k) r.period();
  EXPECT_TRUE(r.all_enabled());
  EXPECT_EQ(r.master().counters().fault_resets, 2U);
}

TEST(MasterAgainstEmulator, ADriveThatWillNotEnableIsNamedWithItsState) {
  Rig r;
  r.drive(3).refuse_enable(State::SwitchOnDisabled);
  const hal::DriveInitResult res = r.master().init();
  ASSERT_FALSE(res.ok);
  EXPECT_EQ(res.drive, 3);
  const std::string what = res.what;
  EXPECT_NE(what.find("node 4"), std::string::npos) << what;
  EXPECT_NE(what.find("Switch on disabled"), std::string::npos) << what;
  EXPECT_NE(what.find("Ready to switch on"), std::string::npos) << what;
}

TEST(MasterAgainstEmulator, AnSdoAbortAtBringUpNamesNodeObjectAndCode) {
  Rig r;
  r.drive(1).inject_sdo_abort(0x6083, 0, 0x06090030);
  const hal::DriveInitResult res = r.master().init();
  ASSERT_FALSE(res.ok);
  EXPECT_EQ(res.drive, 1);
  const std::string what = res.what;
  EXPECT_NE(what.find("node 2"), std::string::npos) << what;
  EXPECT_NE(what.find("0x6083"), std::string::npos) << what;
  EXPECT_NE(what.find("0x06090030"), std::string::npos) << what;
}

TEST(MasterAgainstEmulator, CorruptAndUnknownFramesAreCountedAndChangeNothing) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  r.drive_at(2.0F);
  for (int k = 0; k < 30; ++k) r.period();
  r.drive(0).inject_unknown_frames(10);
  r.drive(3).inject_corrupt_frames(2);  // two SYNCs: fewer than the heartbeat loss needs
  for (int k = 0; k < 30; ++k) r.period();
  EXPECT_GE(r.master().counters().unknown_cob, 10U);
  EXPECT_GE(r.master().counters().malformed, 4U);
  EXPECT_TRUE(r.all_enabled());
  EXPECT_EQ(r.master().counters().faults, 0U);
  EXPECT_NEAR(r.drive(3).wheel_speed_radps(), 2.0, 0.01);
}

TEST(MasterAgainstEmulator, WhenTheMasterDiesTheDrivesStopOnTheirOwn) {
  Rig r;
  ASSERT_TRUE(r.up_and_enabled());
  r.drive_at(4.0F);
  for (int k = 0; k < 60; ++k) r.period();
  ASSERT_NEAR(r.max_wheel_speed(), 4.0, 0.01);
  const TimeNs died_at = r.clock().t;
  TimeNs stopped_at = -1;
  for (int k = 0; k < 100 && stopped_at < 0; ++k) {
    r.period(/*master_alive=*/false);  // no SYNC, no RPDO, no heartbeat: a killed controller
    if (r.max_wheel_speed() < 0.01) stopped_at = r.clock().t;
  }
  ASSERT_GE(stopped_at, 0) << "a drive kept turning after the master died";
  std::printf(
      "master dead: every wheel < 0.01 rad/s after %.0f ms (consumer time 150 ms, "
      "quick stop 50 rad/s^2)\n",
      double(stopped_at - died_at) / 1e6);
  // Consumer time 150 ms after the last heartbeat (up to 50 ms before), then 4 rad/s on the
  // 50 rad/s^2 quick-stop ramp (80 ms) and the velocity loop's lag.
  EXPECT_LE(stopped_at - died_at, 350 * kMs);
  for (int k = 0; k < 10; ++k) r.period(false);  // the fault reaction ends in Fault
  for (int i = 0; i < kWheels; ++i) {
    EXPECT_TRUE(r.drive(i).master_heartbeat_lost()) << i;
    EXPECT_EQ(r.drive(i).state(), State::Fault) << i;
  }
}

}  // namespace
}  // namespace carril::sim
