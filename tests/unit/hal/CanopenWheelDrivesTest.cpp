// CanopenWheelDrives on the loopback bus against scripted CiA 402 slaves: bring-up, the
// success path, config checks, bring-up failures, frames that are ignored and counted, bounded
// reads. The fault reactions are in CanopenFaultsTest.cpp.
#include "hal/canopen/CanopenWheelDrives.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "CanopenTestBench.hpp"

namespace carril::hal::canopen::test {
namespace {

// gtest only (no gmock here): whether `text` contains `part`.
::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" lacks \"" << part << "\"";
}

std::string init_error(Bench& b) {
  const DriveInitResult r = b.drives().init();
  EXPECT_FALSE(r.ok);
  return r.what;
}

TEST(CanopenBringUp, WritesEverySetupObjectInOrderThenStartsEveryDrive) {
  Bench b;
  const DriveInitResult r = b.drives().init();
  ASSERT_TRUE(r.ok) << r.what;
  for (int i = 0; i < 2; ++i) {
    const DriveSetup& setup = b.config().drive[i];
    SdoWrite want[kMaxSetupWrites];
    const std::size_t n = setup_writes(setup, want);
    const Slave& s = b.slave(setup.node);
    ASSERT_EQ(s.writes.size(), n) << "drive " << i;
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(s.writes[k].index, want[k].index) << k;
      EXPECT_EQ(s.writes[k].sub, want[k].subindex) << k;
      EXPECT_EQ(s.writes[k].value, want[k].value) << k;
    }
    EXPECT_EQ(s.boot_ups, 1);
    EXPECT_EQ(s.nmt_starts, 1);
    EXPECT_EQ(s.nmt, Slave::Nmt::Operational);
    // init() proved the power state machine: enabled once, then back to disabled.
    EXPECT_EQ(s.state, Slave::S::SwitchOnDisabled);
    bool enabled_once = false;
    for (const Slave::Rpdo& p : s.rpdos) enabled_once = enabled_once || p.cw == 0x000F;
    EXPECT_TRUE(enabled_once);
    EXPECT_EQ(b.feedback(i).state, DriveState::Disabled);
  }
  EXPECT_TRUE(b.drives().bring_up_result().ok);
  EXPECT_EQ(b.drives().counters().faults, 0U);
  EXPECT_STREQ(b.drives().last_fault(), "");
}

TEST(CanopenWheelDrives, VelocityReachesTheBusInCountsPerSecondAndComesBackInRadPerSecond) {
  Bench b;
  ASSERT_TRUE(b.up_and_enabled()) << b.drives().bring_up_result().what;
  const float sp[2] = {1.0F, -2.0F};
  b.drives().set_velocity(sp, 2);
  b.ticks(3);
  // 1 rad/s x gear 10 x 4096 counts / 2 pi = 6518.99 counts/s.
  EXPECT_EQ(b.slave(2).rpdos.back().target, 6519);
  EXPECT_EQ(b.slave(3).rpdos.back().target, -13038);
  EXPECT_EQ(b.slave(2).rpdos.back().cw, 0x000F);
  b.ticks(100);  // 1 s
  const WheelFeedback left = b.feedback(0), right = b.feedback(1);
  EXPECT_EQ(left.state, DriveState::Enabled);
  EXPECT_EQ(left.fault, DriveFault::None);
  EXPECT_NEAR(left.velocity_radps, 1.0, 1e-3);
  EXPECT_NEAR(right.velocity_radps, -2.0, 1e-3);
  EXPECT_NEAR(left.position_rad, 1.0, 0.03);  // ~1 s at 1 rad/s
  EXPECT_NEAR(right.position_rad, -2.0, 0.06);
  EXPECT_EQ(left.stamp_ns, b.clock().t - 10 * kMs);  // sampled at the previous period's SYNC
  for (const Slave::Rpdo& p : b.slave(2).rpdos) EXPECT_EQ(p.cw & 0x0100, 0) << "halt bit set";
}

TEST(CanopenWheelDrives, AnInvertedDriveGetsNegatedSpeedsAndReportsWheelSpeeds) {
  CanopenConfig cfg = Bench::default_config();
  cfg.drive[1].inverted = true;  // the right-hand motor mounted mirrored
  Bench b(cfg);
  ASSERT_TRUE(b.up_and_enabled()) << b.drives().bring_up_result().what;
  const float sp[2] = {1.0F, 1.0F};  // both wheels forward
  b.drives().set_velocity(sp, 2);
  b.ticks(3);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 6519);
  EXPECT_EQ(b.slave(3).rpdos.back().target, -6519);  // the mirrored motor turns backwards
  b.ticks(100);
  EXPECT_NEAR(b.feedback(0).velocity_radps, 1.0, 1e-3);
  EXPECT_NEAR(b.feedback(1).velocity_radps, 1.0, 1e-3);  // ... and the wheel forwards
  EXPECT_NEAR(b.feedback(1).position_rad, 1.0, 0.03);
}

TEST(CanopenWheelDrives, OneSyncAndOneRpdoPerDrivePerPeriodAndTheMasterHeartbeatAtItsRate) {
  Bench b;
  ASSERT_TRUE(b.drives().init().ok);
  b.tick();  // the bring-up's last frames reach the slaves
  const std::uint64_t syncs = b.drives().counters().syncs;
  const std::size_t rpdos = b.slave(2).rpdos.size();
  const int hbs = b.slave(2).master_hbs;
  b.ticks(100);  // 1 s
  EXPECT_EQ(b.drives().counters().syncs - syncs, 100U);
  EXPECT_EQ(b.slave(2).syncs > 0, true);
  EXPECT_EQ(b.slave(2).rpdos.size() - rpdos, 100U);
  EXPECT_EQ(b.slave(3).rpdos.size(), b.slave(2).rpdos.size());
  EXPECT_NEAR(b.slave(2).master_hbs - hbs, 50, 1);  // every 20 ms
}

TEST(CanopenWheelDrives, TargetIsZeroUntilOperationEnabled) {
  Bench b;
  ASSERT_TRUE(b.drives().init().ok);
  const float sp[2] = {3.0F, 3.0F};
  b.drives().set_velocity(sp, 2);
  b.ticks(5);  // not enabled: zero
  b.drives().enable();
  const std::size_t from = b.slave(2).rpdos.size() - 5;
  b.ticks(6);
  const std::vector<Slave::Rpdo>& r = b.slave(2).rpdos;
  bool moved = false;
  for (std::size_t k = from; k < r.size(); ++k) {
    if (r[k].cw != 0x000F) EXPECT_EQ(r[k].target, 0) << "cw " << r[k].cw;
    moved = moved || r[k].target != 0;
  }
  EXPECT_TRUE(moved);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  b.drives().disable();
  b.ticks(2);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 0);
  EXPECT_EQ(b.feedback(0).state, DriveState::Disabled);
  EXPECT_EQ(b.slave(2).state, Slave::S::SwitchOnDisabled);
}

TEST(CanopenWheelDrives, PositionIsUnwrappedAcrossTheCounterWrap) {
  Bench b;
  b.slave(2).position = 0x7FFFF000U;  // about to wrap from INT32_MAX to INT32_MIN
  ASSERT_TRUE(b.up_and_enabled());
  const double before = b.feedback(0).position_rad;
  const float sp[2] = {10.0F, 0.0F};  // 65190 counts/s: past the wrap within 0.1 s
  b.drives().set_velocity(sp, 2);
  b.ticks(50);
  const double after = b.feedback(0).position_rad;
  EXPECT_GT(b.slave(2).position, 0x80000000U);  // the counter wrapped
  EXPECT_NEAR(after - before, 10.0 * 0.48, 0.2);
}

TEST(CanopenConfig, ABadValueFailsInitNamingTheField) {
  struct Case {
    const char* field;
    void (*mutate)(CanopenConfig&);
  };
  const Case cases[] = {
      {"wheels = 0", [](CanopenConfig& c) { c.wheels = 0; }},
      {"wheels = 5", [](CanopenConfig& c) { c.wheels = 5; }},
      {"master_node = 0", [](CanopenConfig& c) { c.master_node = 0; }},
      {"drive[1].node = 2: drive[0]", [](CanopenConfig& c) { c.drive[1].node = 2; }},
      {"drive[0].node = 0", [](CanopenConfig& c) { c.drive[0].node = 0; }},
      {"drive[1].node = 127", [](CanopenConfig& c) { c.drive[1].node = 127; }},
      {"drive[0].units", [](CanopenConfig& c) { c.drive[0].units.counts_per_rev = 0.0; }},
      {"drive[1].units", [](CanopenConfig& c) { c.drive[1].units.gear_ratio = NAN; }},
      {"drive[1].master_node = 100", [](CanopenConfig& c) { c.drive[1].master_node = 100; }},
      {"drive[0].master_timeout_ms = 20",
       [](CanopenConfig& c) { c.drive[0].master_timeout_ms = 20; }},
      {"heartbeat_consumer_ns = 135 ms",  // + 2 x 10 ms > 3 x 50 ms
       [](CanopenConfig& c) { c.heartbeat_consumer_ns = 135 * kMs; }},
      {"control_period_ns = 0", [](CanopenConfig& c) { c.control_period_ns = 0; }},
      {"heartbeat_consumer_ns = 160 ms",
       [](CanopenConfig& c) { c.heartbeat_consumer_ns = 160 * kMs; }},
      {"heartbeat_consumer_ns = 50 ms",
       [](CanopenConfig& c) { c.heartbeat_consumer_ns = 50 * kMs; }},
      {"sdo_timeout_ns = 0", [](CanopenConfig& c) { c.sdo_timeout_ns = 0; }},
      {"max_reads = 0", [](CanopenConfig& c) { c.max_reads = 0; }},
      {"backoff_max_ns", [](CanopenConfig& c) { c.backoff_max_ns = 1; }},
  };
  for (const Case& k : cases) {
    CanopenConfig c = Bench::default_config();
    k.mutate(c);
    Bench b(c);
    EXPECT_TRUE(contains(b.drives().config_error(), k.field));
    const DriveInitResult r = b.drives().init();
    EXPECT_FALSE(r.ok) << k.field;
    EXPECT_TRUE(contains(r.what, k.field));
    EXPECT_EQ(b.bus().endpoint(0).counters().tx_frames, 0U) << "nothing sent on a bad config";
  }
  Bench good;
  EXPECT_STREQ(good.drives().config_error(), "");
}

TEST(CanopenBringUp, SdoAbortNamesDriveNodeObjectAndAbortCode) {
  Bench b;
  b.slave(3).abort_index = 0x6083;
  b.slave(3).abort_code = 0x06090030;
  const DriveInitResult r = b.drives().init();
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.drive, 1);
  EXPECT_STREQ(r.what,
               "drive 1 (node 3): SDO write 0x6083:00 = 162975 (profile acceleration) aborted: "
               "0x06090030 value range exceeded");
  EXPECT_EQ(b.slave(3).nmt_starts, 0);  // never started half-configured
}

TEST(CanopenBringUp, SdoTimeoutNamesDriveNodeAndObject) {
  CanopenConfig c = Bench::default_config();
  c.name[0] = "left";
  c.name[1] = "right";
  Bench b(c);
  b.slave(2).abort_index = 0x1017;  // no answer
  const TimeNs t0 = b.clock().t;
  const std::string what = init_error(b);
  EXPECT_EQ(what,
            "drive 0 (left, node 2): SDO write 0x1017:00 = 50 (producer heartbeat time): no "
            "response within 0.050 s");
  EXPECT_LT(b.clock().t - t0, 1000 * kMs);
}

TEST(CanopenBringUp, NoBootUpIsNamedWithTheTimeout) {
  Bench b;
  b.slave(3).no_boot = true;
  const TimeNs t0 = b.clock().t;
  EXPECT_EQ(init_error(b),
            "drive 1 (node 3): no boot-up within 1.0 s after NMT reset communication");
  EXPECT_NEAR(double(b.clock().t - t0), 1.0e9, 0.05e9);
}

TEST(CanopenBringUp, ADriveThatWillNotEnableNamesItsStateAndTheOneItWaitedFor) {
  Bench b;
  b.slave(3).stuck = true;
  const std::string what = init_error(b);
  EXPECT_TRUE(contains(what,
                       "drive 1 (node 3): stuck in Switch on disabled, waiting for Ready to "
                       "switch on after 1.0"));
  EXPECT_EQ(b.drives().bring_up_result().drive, 1);
}

TEST(CanopenBringUp, ADriveThatPowersUpInFaultGetsOneResetAndComesUp) {
  Bench b;
  b.slave(2).state = Slave::S::Fault;
  const DriveInitResult r = b.drives().init();
  ASSERT_TRUE(r.ok) << r.what;
  EXPECT_EQ(b.slave(2).resets_seen, 1);
  EXPECT_EQ(b.slave(3).resets_seen, 0);
}

TEST(CanopenWheelDrives, UnknownNodesUnknownIdsAndWrongLengthsAreCountedAndNeverActedOn) {
  Bench b;
  ASSERT_TRUE(b.up_and_enabled());
  const float sp[2] = {1.0F, 1.0F};
  b.drives().set_velocity(sp, 2);
  b.ticks(3);
  const CanopenCounters before = b.drives().counters();
  CanBus& port = b.slaves().port();
  auto frame = [](std::uint32_t id, std::uint8_t len) {
    CanFrame f;
    f.id = id;
    f.len = len;
    f.data[0] = 0x08;  // a Fault statusword, an EMCY code byte: must not be believed
    f.data[1] = 0x23;
    return f;
  };
  port.send(frame(0x709, 1));  // heartbeat of node 9: unknown node
  port.send(frame(0x089, 8));  // EMCY of node 9: unknown node
  port.send(frame(0x182, 5));  // TPDO1 of node 2, one byte short: malformed
  port.send(frame(0x082, 4));  // EMCY of node 2, short: malformed
  port.send(frame(0x702, 2));  // heartbeat of node 2, too long: malformed
  port.send(frame(0x282, 8));  // TPDO2 too long: malformed
  CanFrame rtr = frame(0x182, 6);
  rtr.rtr = true;
  port.send(rtr);              // remote frame: malformed
  port.send(frame(0x302, 8));  // TPDO3 / RPDO2 range: not consumed
  port.send(frame(0x0FF, 8));  // EMCY of node 127, the master's own id: unknown node
  CanFrame ext = frame(0x182, 6);
  ext.extended = true;
  port.send(ext);  // extended id: not CANopen
  b.ticks(3);
  const CanopenCounters& after = b.drives().counters();
  EXPECT_EQ(after.unknown_node - before.unknown_node, 3U);
  EXPECT_EQ(after.malformed - before.malformed, 5U);
  EXPECT_EQ(after.unknown_cob - before.unknown_cob, 2U);
  EXPECT_EQ(after.emcy, before.emcy);
  EXPECT_EQ(after.faults, 0U);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_NEAR(b.feedback(0).velocity_radps, 1.0, 1e-3);
  EXPECT_EQ(b.slave(2).rpdos.back().target, 6519);
}

TEST(CanopenWheelDrives, ReadsAtMostMaxReadsFramesPerSync) {
  CanopenConfig c = Bench::default_config();
  c.max_reads = 6;
  Bench b(c);
  ASSERT_TRUE(b.drives().init().ok);
  b.tick();
  CanFrame junk;
  junk.id = 0x709;  // an unknown node's heartbeat
  junk.len = 1;
  for (int k = 0; k < 40; ++k) b.slaves().port().send(junk);
  b.bus().transfer();
  for (int k = 0; k < 3; ++k) {
    const std::uint64_t read = b.drives().counters().frames_read;
    b.drives().sync();
    EXPECT_EQ(b.drives().counters().frames_read - read, 6U);
  }
}

TEST(CanopenWheelDrives, SyncBeforeInitSendsNothingAndReadsDisabled) {
  Bench b;
  b.drives().enable();
  b.drives().sync();
  b.bus().transfer();
  EXPECT_EQ(b.bus().endpoint(0).counters().tx_frames, 0U);
  EXPECT_EQ(b.feedback(1).state, DriveState::Disabled);
  EXPECT_EQ(b.drives().count(), 2);
}

}  // namespace
}  // namespace carril::hal::canopen::test
