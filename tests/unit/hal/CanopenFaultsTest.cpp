// The fault reactions of CanopenWheelDrives (issue 9, item 7), each on the loopback bus with a
// defined, logged and counted outcome: a lost heartbeat, an EMCY, a drive that faults again
// after its one reset, bus-off and an interface that refuses frames.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "CanopenTestBench.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"

namespace carril::hal::canopen::test {
namespace {

constexpr std::uint16_t kQuickStopCw = 0x0002;

// The first RPDO at or after `from` that stops the drive (quick stop, target 0); -1 none.
TimeNs first_stop(const Slave& s, TimeNs from) {
  for (const Slave::Rpdo& p : s.rpdos) {
    if (p.t >= from && p.cw == kQuickStopCw && p.target == 0) return p.t;
  }
  return -1;
}

// Every RPDO from `from` on stops the drive.
bool stopped_since(const Slave& s, TimeNs from) {
  for (const Slave::Rpdo& p : s.rpdos) {
    if (p.t >= from && (p.target != 0 || p.cw == 0x000F)) return false;
  }
  return true;
}

class CanopenFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(b.up_and_enabled()) << b.drives().bring_up_result().what;
    const float sp[2] = {2.0F, 2.0F};
    b.drives().set_velocity(sp, 2);
    b.ticks(10);
    ASSERT_NE(b.slave(2).rpdos.back().target, 0);
  }

  Bench b;
};

TEST_F(CanopenFaults, LostHeartbeatStopsEveryWheelWithinThreeHeartbeatPeriods) {
  Slave& dead = b.slave(3);
  const TimeNs last_hb = dead.next_hb - 50 * kMs;  // it sent its last heartbeat then
  dead.dead = true;
  b.ticks(30);
  const TimeNs stop2 = first_stop(b.slave(2), last_hb);
  const TimeNs stop3 = first_stop(dead, last_hb);
  ASSERT_GE(stop2, 0);
  ASSERT_GE(stop3, 0);
  EXPECT_LE(stop2 - last_hb, 3 * 50 * kMs);
  EXPECT_LE(stop3 - last_hb, 3 * 50 * kMs);
  EXPECT_GT(stop2 - last_hb, 125 * kMs);  // not before the consumer time
  EXPECT_TRUE(stopped_since(b.slave(2), stop2));
  const WheelFeedback lost = b.feedback(1), other = b.feedback(0);
  EXPECT_EQ(lost.state, DriveState::Fault);
  EXPECT_EQ(lost.fault, DriveFault::HeartbeatLost);
  EXPECT_EQ(other.state, DriveState::QuickStop);
  EXPECT_EQ(b.drives().counters().heartbeat_losses, 1U);
  EXPECT_EQ(b.drives().counters().faults, 1U);
  EXPECT_EQ(std::string(b.drives().last_fault()).rfind("drive 1 (node 3): heartbeat lost", 0), 0U)
      << b.drives().last_fault();

  // enable() alone does not resume, nor does reset_faults() while the drive is silent.
  b.drives().enable();
  b.drives().reset_faults();
  b.ticks(10);
  EXPECT_TRUE(stopped_since(b.slave(2), stop2));
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);

  // Heard again, reset, enabled: running.
  dead.dead = false;
  b.ticks(10);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);  // latched until reset_faults()
  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).fault, DriveFault::None);
  EXPECT_NE(b.slave(3).rpdos.back().target, 0);
}

TEST_F(CanopenFaults, EmcyFaultsTheDriveWithItsDecodedCodeAndStopsEveryWheel) {
  const TimeNs t0 = b.clock().t;
  b.slaves().fault(b.slave(2), 0x2310);
  b.ticks(2);
  const WheelFeedback f = b.feedback(0);
  EXPECT_EQ(f.state, DriveState::Fault);
  EXPECT_EQ(f.fault, DriveFault::Overcurrent);
  EXPECT_STREQ(b.drives().last_fault(),
               "drive 0 (node 2): EMCY 0x2310 continuous over-current (error register 0x01)");
  EXPECT_EQ(b.drives().last_emcy_code(0), 0x2310);
  EXPECT_EQ(b.drives().emcy_count(0), 1U);
  EXPECT_EQ(b.drives().counters().emcy, 1U);
  EXPECT_EQ(b.drives().latched_fault(0), 0x2310);
  EXPECT_EQ(b.feedback(1).state, DriveState::QuickStop);
  const TimeNs stop = first_stop(b.slave(3), t0);
  ASSERT_GE(stop, 0);
  EXPECT_LE(stop - t0, 20 * kMs);  // the period after the EMCY arrived
  EXPECT_TRUE(stopped_since(b.slave(3), stop));
}

TEST_F(CanopenFaults, EmcyErrorResetIsCountedNotLatched) {
  CanFrame e;
  e.id = kEmcyBase + 2;
  e.len = 8;  // code 0x0000: error reset or no error
  b.slaves().send(b.slave(2), e);
  b.ticks(2);
  EXPECT_EQ(b.drives().counters().emcy, 1U);
  EXPECT_EQ(b.drives().counters().faults, 0U);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
}

TEST_F(CanopenFaults, FaultStatuswordWithoutEmcyIsAFaultToo) {
  Slave& s = b.slave(3);
  s.state = Slave::S::Fault;  // no EMCY sent
  b.ticks(3);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(1).fault), kFaultGeneric);
  EXPECT_EQ(b.feedback(0).state, DriveState::QuickStop);
  EXPECT_STREQ(b.drives().last_fault(), "drive 1 (node 3): in Fault (statusword 0x0008), no EMCY");
}

TEST_F(CanopenFaults, OneResetPerResetFaultsThenADriveThatFaultsAgainStaysStopped) {
  Slave& s = b.slave(2);
  s.refault = 0x7121;  // motor blocked, every time it is enabled
  b.slaves().fault(s, 0x7121);
  b.ticks(3);
  ASSERT_EQ(b.feedback(0).state, DriveState::Fault);

  b.drives().reset_faults();
  b.ticks(3);
  EXPECT_EQ(s.resets_seen, 1);
  EXPECT_EQ(s.state, Slave::S::SwitchOnDisabled);
  b.drives().enable();
  b.ticks(100);  // it faults again on enabling; nobody resets it
  EXPECT_EQ(s.resets_seen, 1);
  EXPECT_EQ(b.drives().counters().fault_resets, 1U);
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  EXPECT_EQ(b.feedback(0).fault, static_cast<DriveFault>(0x7121));
  EXPECT_EQ(b.feedback(1).state, DriveState::QuickStop);
  EXPECT_TRUE(stopped_since(b.slave(3), b.clock().t - 500 * kMs));
  EXPECT_EQ(b.drives().emcy_count(0), 2U);

  b.drives().reset_faults();  // one more call, one more attempt, no more
  b.ticks(50);
  EXPECT_EQ(s.resets_seen, 2);
  EXPECT_EQ(b.drives().counters().fault_resets, 2U);
}

TEST_F(CanopenFaults, BusOffStopsEverythingProbesWithBackoffAndResumesOnlyWhenReEnabled) {
  const TimeNs t0 = b.clock().t;
  b.bus().force_bus_off(0);
  b.tick();
  EXPECT_TRUE(b.drives().bus_down());
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(b.feedback(i).state, DriveState::Fault);
    EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(i).fault), kFaultBusDown);
  }
  EXPECT_EQ(b.drives().counters().bus_offs, 1U);
  EXPECT_EQ(b.drives().counters().error_frames, 1U);
  EXPECT_EQ(std::string(b.drives().last_fault()).rfind("CAN bus-off (error frame)", 0), 0U)
      << b.drives().last_fault();

  // Probes at 0.1, 0.3, 0.7, 1.5, 3.1, 5.1, 7.1 s: doubling up to 2 s.
  std::vector<TimeNs> probes;
  std::uint64_t seen = b.drives().counters().probes;
  while (b.clock().t - t0 < 7200 * kMs) {
    b.tick();
    if (b.drives().counters().probes != seen) {
      seen = b.drives().counters().probes;
      probes.push_back(b.clock().t - t0);
    }
  }
  const TimeNs want[] = {110, 310, 710, 1510, 3110, 5110, 7110};
  ASSERT_EQ(probes.size(), std::size(want));
  for (std::size_t k = 0; k < probes.size(); ++k) {
    EXPECT_NEAR(double(probes[k]), double(want[k] * kMs), 10.0 * kMs) << k;
  }
  // Meanwhile the drives lost the master's heartbeat and faulted on their own.
  EXPECT_EQ(b.slave(2).state, Slave::S::Fault);

  b.bus().restart(0);
  for (int k = 0; k < 300 && b.drives().bus_down(); ++k) b.tick();
  EXPECT_FALSE(b.drives().bus_down());
  b.drives().enable();  // not enough: the faults are latched
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 0);

  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
  EXPECT_EQ(b.slave(2).resets_seen, 1);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 13038);
}

TEST(CanopenBusOff, AfterAShortBusOffResetWaitsUntilTheDrivesAreHeardAgain) {
  CanopenConfig c = Bench::default_config();
  c.backoff_min_ns = 20 * kMs;  // back well within the consumer time: no drive is lost
  Bench b(c);
  ASSERT_TRUE(b.up_and_enabled());
  b.bus().force_bus_off(0);
  b.slave(2).dead = b.slave(3).dead = true;  // nothing heard from them meanwhile
  b.tick();
  ASSERT_TRUE(b.drives().bus_down());
  b.bus().restart(0);
  for (int k = 0; k < 30 && b.drives().bus_down(); ++k) b.tick();
  ASSERT_FALSE(b.drives().bus_down());
  EXPECT_EQ(b.drives().counters().heartbeat_losses, 0U);
  b.drives().reset_faults();  // the bus is back but no drive was heard since: latches stay
  b.drives().enable();
  b.slave(2).dead = b.slave(3).dead = false;
  b.ticks(2);
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 0);
  b.ticks(10);
  b.drives().reset_faults();  // heard since: cleared
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
}

TEST_F(CanopenFaults, AnInterfaceThatRefusesFramesIsTreatedAsBusOff) {
  b.master_port().down = true;
  b.tick();
  EXPECT_TRUE(b.drives().bus_down());
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  EXPECT_EQ(b.drives().counters().send_refused, 1U);
  EXPECT_EQ(std::string(b.drives().last_fault()).rfind("CAN send refused", 0), 0U)
      << b.drives().last_fault();
  b.ticks(50);
  EXPECT_EQ(b.drives().counters().send_refused, 1U + b.drives().counters().probes);
  b.master_port().down = false;
  for (int k = 0; k < 300 && b.drives().bus_down(); ++k) b.tick();
  ASSERT_FALSE(b.drives().bus_down());
  b.ticks(10);
  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
}

TEST_F(CanopenFaults, ADriveThatRebootsWhileRunningIsAFaultThatResetDoesNotClear) {
  b.slaves().port().send(heartbeat(3, NmtState::BootUp));
  b.ticks(2);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(1).fault), kFaultRebooted);
  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(5);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_TRUE(stopped_since(b.slave(2), b.clock().t - 30 * kMs));
}

TEST_F(CanopenFaults, ADriveThatLeavesOperationalIsAFaultUntilStartedAgain) {
  b.slave(2).nmt = Slave::Nmt::PreOp;  // its PDOs stop, its heartbeat says pre-operational
  b.ticks(6);
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(0).fault), kFaultNotOperational);
  EXPECT_STREQ(b.drives().last_fault(),
               "drive 0 (node 2): left Operational: heartbeat says pre-operational");
  const TimeNs t = b.clock().t;
  b.ticks(3);
  EXPECT_TRUE(stopped_since(b.slave(3), t));
  const int starts = b.slave(2).nmt_starts;
  b.drives().reset_faults();  // sends NMT start; the latch stays until the heartbeat agrees
  b.ticks(6);
  EXPECT_EQ(b.slave(2).nmt_starts, starts + 1);
  EXPECT_EQ(b.feedback(0).state, DriveState::Fault);
  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
}

TEST_F(CanopenFaults, AnEnableThatDoesNotFinishAtRunTimeNamesTheStuckState) {
  b.drives().quick_stop();
  b.ticks(3);
  b.drives().disable();
  b.ticks(3);
  b.slave(3).stuck = true;
  b.drives().enable();
  b.ticks(110);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(1).fault), kFaultEnableTimeout);
  EXPECT_EQ(std::string(b.drives().last_fault())
                .rfind("drive 1 (node 3): stuck in Switch on disabled, waiting for Ready to switch "
                       "on after 1.0",
                       0),
            0U)
      << b.drives().last_fault();
}

}  // namespace
}  // namespace carril::hal::canopen::test
