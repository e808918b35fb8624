// The emulated CiA 402 drive, driven from the master's side over the loopback bus with the
// master's own pieces (hal/canopen frames, SdoClient, PowerStateMachine, DriveSetup).
#include "host_sim/drives/DriveEmulator.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/DriveSetup.hpp"
#include "hal/canopen/Frames.hpp"
#include "hal/canopen/SdoClient.hpp"

namespace carril::sim {
namespace {

namespace canopen = hal::canopen;
namespace cia402 = hal::cia402;
using hal::CanFrame;
using hal::SdoResult;
using hal::SdoState;
using hal::TimeNs;
using State = cia402::State;

constexpr std::uint8_t kNode = 3;
constexpr std::uint8_t kMaster = 127;
constexpr TimeNs kMs = 1'000'000;
constexpr TimeNs kPeriod = 10 * kMs;  // the master's control period

hal::LoopbackCanBus::Config bus_config() {
  hal::LoopbackCanBus::Config c;
  c.endpoints = 2;
  c.tx_depth = 64;
  c.rx_depth = 256;
  return c;
}

// Endpoint 0 is the master, endpoint 1 the drive.
class DriveEmulatorTest : public ::testing::Test {
 protected:
  explicit DriveEmulatorTest(std::int64_t initial_position = 0)
      : bus_(bus_config()),
        drive_(bus_.endpoint(1), drive_config(initial_position)),
        sdo_(bus_.endpoint(0), hal::SdoClient::Config{kNode, 50 * kMs}) {
    setup_.node = kNode;
    setup_.units = units();
    setup_.master_node = kMaster;
  }

  static cia402::DriveUnits units() {
    cia402::DriveUnits u;
    u.counts_per_rev = 4096.0;
    u.gear_ratio = 10.0;
    return u;
  }
  static DriveEmulator::Config drive_config(std::int64_t initial_position) {
    DriveEmulator::Config c;
    c.node = kNode;
    c.units = units();
    c.velocity_tau_s = 0.02;
    c.initial_position_counts = initial_position;
    return c;
  }

  hal::CanBus& master() { return bus_.endpoint(0); }

  // Time passes by dt: the master's frames reach the drive, it steps, its frames come back.
  void tick(TimeNs dt = kPeriod) {
    bus_.transfer();
    now_ += dt;
    drive_.step(now_, double(dt) * 1e-9);
    bus_.transfer();
    CanFrame f;
    while (master().receive(f)) {
      rx_.push_back(f);
      sdo_.on_frame(f);
    }
    sdo_.poll(now_);
  }
  void run(TimeNs duration, TimeNs dt = kPeriod) {
    for (TimeNs t = 0; t < duration; t += dt) tick(dt);
  }

  SdoResult finish_sdo() {
    for (int i = 0; i < 100 && sdo_.busy(); ++i) tick(kMs);
    return sdo_.result();
  }
  SdoResult download(std::uint16_t index, std::uint8_t sub, std::uint32_t value,
                     std::uint8_t size) {
    EXPECT_TRUE(sdo_.start_download(index, sub, value, size));
    return finish_sdo();
  }
  SdoResult upload(std::uint16_t index, std::uint8_t sub) {
    EXPECT_TRUE(sdo_.start_upload(index, sub));
    return finish_sdo();
  }

  // Power-on, every bring-up write of docs/can-protocol.md, NMT start.
  void bring_up() {
    tick();
    canopen::SdoWrite writes[canopen::kMaxSetupWrites];
    const std::size_t n = canopen::setup_writes(setup_, writes);
    for (std::size_t i = 0; i < n; ++i) {
      const SdoResult r =
          download(writes[i].index, writes[i].subindex, writes[i].value, writes[i].size);
      ASSERT_EQ(r.state, SdoState::Done) << r.message;
    }
    master().send(canopen::nmt(canopen::NmtCommand::Start, kNode));
    tick();
    ASSERT_EQ(drive_.nmt_state(), canopen::NmtState::Operational);
  }

  // What the master saw in one control period.
  struct Seen {
    bool tpdo1 = false, tpdo2 = false;
    std::uint16_t sw = 0;
    std::int32_t velocity = 0, position = 0;
  };
  // One control period: the master's heartbeat (while alive), RPDO1, SYNC; the drive steps.
  Seen cycle(std::uint16_t cw, double target_radps) {
    if (master_alive_) {
      master().send(canopen::heartbeat(kMaster, canopen::NmtState::Operational));
    }
    master().send(canopen::rpdo1(kNode, cw, cia402::to_counts_per_s(target_radps, units())));
    master().send(canopen::sync_frame());
    const std::size_t first = rx_.size();
    tick();
    Seen s;
    for (std::size_t i = first; i < rx_.size(); ++i) {
      s.tpdo1 |= canopen::decode_tpdo1(rx_[i], kNode, s.sw, s.velocity);
      s.tpdo2 |= canopen::decode_tpdo2(rx_[i], kNode, s.position);
    }
    return s;
  }
  // The master's power state machine toward `goal`, one controlword per period; the states
  // the drive reported, in order, without repeats.
  std::vector<State> drive_to(cia402::Goal goal, double target_radps = 0.0, int periods = 10) {
    std::vector<State> seen;
    std::uint16_t cw = cia402::kCwDisableVoltage;
    for (int i = 0; i < periods; ++i) {
      const Seen s = cycle(cw, target_radps);
      if (!s.tpdo1) continue;
      cw = psm_.step(s.sw, goal);
      if (seen.empty() || seen.back() != psm_.state()) seen.push_back(psm_.state());
    }
    return seen;
  }
  // Frames with COB-ID `id` the master received since index `from`.
  std::vector<CanFrame> frames(std::uint32_t id, std::size_t from = 0) const {
    std::vector<CanFrame> out;
    for (std::size_t i = from; i < rx_.size(); ++i) {
      if (rx_[i].id == id) out.push_back(rx_[i]);
    }
    return out;
  }
  std::vector<canopen::Emcy> emcys(std::size_t from = 0) const {
    std::vector<canopen::Emcy> out;
    canopen::Emcy e;
    for (std::size_t i = from; i < rx_.size(); ++i) {
      if (canopen::decode_emcy(rx_[i], e)) out.push_back(e);
    }
    return out;
  }

  hal::LoopbackCanBus bus_;
  DriveEmulator drive_;
  hal::SdoClient sdo_;
  canopen::DriveSetup setup_;
  cia402::PowerStateMachine psm_;
  TimeNs now_ = 0;
  bool master_alive_ = true;
  std::vector<CanFrame> rx_;
};

TEST_F(DriveEmulatorTest, SendsBootUpAtPowerOnAndAfterEachReset) {
  tick();
  ASSERT_EQ(rx_.size(), 1U);
  std::uint8_t node = 0, state = 0xFF;
  ASSERT_TRUE(canopen::decode_heartbeat(rx_[0], node, state));
  EXPECT_EQ(node, kNode);
  EXPECT_EQ(state, 0x00);  // boot-up
  EXPECT_EQ(drive_.nmt_state(), canopen::NmtState::PreOperational);
  EXPECT_EQ(drive_.state(), State::SwitchOnDisabled);

  // Reset communication keeps the application objects, reset node restores them too.
  ASSERT_EQ(download(0x6083, 0, 1234, 4).state, SdoState::Done);
  ASSERT_EQ(download(0x1017, 0, 20, 2).state, SdoState::Done);
  master().send(canopen::nmt(canopen::NmtCommand::ResetCommunication, kNode));
  tick();
  EXPECT_EQ(frames(0x700 + kNode).size(), 2U);
  EXPECT_EQ(upload(0x1017, 0).value, 0U);
  EXPECT_EQ(upload(0x6083, 0).value, 1234U);
  master().send(canopen::nmt(canopen::NmtCommand::ResetNode, 0));  // 0: every node
  tick();
  EXPECT_EQ(frames(0x700 + kNode).size(), 3U);
  EXPECT_EQ(upload(0x6083, 0).value, 40960U);
  EXPECT_EQ(drive_.counters().boot_ups_sent, 3U);
}

TEST_F(DriveEmulatorTest, NmtStateGatesPdosAndSdo) {
  tick();
  master().send(canopen::sync_frame());
  tick();
  EXPECT_TRUE(frames(0x180 + kNode).empty());  // Pre-operational: no PDOs
  EXPECT_EQ(drive_.counters().frames_ignored_in_state, 1U);
  EXPECT_EQ(upload(0x1000, 0).value, 0x00020192U);  // but SDO

  master().send(canopen::nmt(canopen::NmtCommand::Start, kNode));
  const Seen s = cycle(0, 0.0);
  EXPECT_TRUE(s.tpdo1);
  EXPECT_TRUE(s.tpdo2);
  EXPECT_EQ(cia402::decode_statusword(s.sw), State::SwitchOnDisabled);

  master().send(canopen::nmt(canopen::NmtCommand::Stop, kNode));
  tick();
  EXPECT_EQ(drive_.nmt_state(), canopen::NmtState::Stopped);
  EXPECT_EQ(upload(0x1000, 0).state, SdoState::TimedOut);  // Stopped: no SDO either
  EXPECT_FALSE(cycle(0, 0.0).tpdo1);

  master().send(canopen::nmt(canopen::NmtCommand::EnterPreOperational, kNode));
  tick();
  EXPECT_EQ(drive_.nmt_state(), canopen::NmtState::PreOperational);
  // Another node's NMT command is not for this drive.
  master().send(canopen::nmt(canopen::NmtCommand::Start, kNode + 1));
  tick();
  EXPECT_EQ(drive_.nmt_state(), canopen::NmtState::PreOperational);
}

TEST_F(DriveEmulatorTest, AcceptsEveryBringUpWriteAndReadsItBack) {
  tick();
  canopen::SdoWrite writes[canopen::kMaxSetupWrites];
  const std::size_t n = canopen::setup_writes(setup_, writes);
  std::map<std::pair<std::uint16_t, std::uint8_t>, std::uint32_t> last;
  for (std::size_t i = 0; i < n; ++i) {
    const SdoResult r =
        download(writes[i].index, writes[i].subindex, writes[i].value, writes[i].size);
    EXPECT_EQ(r.state, SdoState::Done) << writes[i].what << ": " << r.message;
    last[{writes[i].index, writes[i].subindex}] = writes[i].value;
  }
  for (const auto& [key, value] : last) {
    const SdoResult r = upload(key.first, key.second);
    EXPECT_EQ(r.state, SdoState::Done) << r.message;
    EXPECT_EQ(r.value, value) << std::hex << key.first << ":" << int(key.second);
  }
  EXPECT_EQ(drive_.counters().sdo_aborts_sent, 0U);
  EXPECT_EQ(upload(0x6061, 0).value, 3U);  // mode display follows 0x6060
}

TEST_F(DriveEmulatorTest, AbortsWithTheCia301CodeThatSaysWhy) {
  tick();
  const struct {
    std::uint16_t index;
    std::uint8_t sub;
    std::uint32_t value;
    std::uint8_t size;
    std::uint32_t code;
  } cases[] = {
      {0x2000, 0, 1, 4, 0x06020000U},            // object does not exist
      {0x6060, 1, 3, 1, 0x06090011U},            // sub-index does not exist
      {0x6041, 0, 0x27, 2, 0x06010002U},         // statusword is read-only
      {0x1000, 0, 0, 4, 0x06010002U},            // device type is const
      {0x6060, 0, 3, 2, 0x06070010U},            // length does not match
      {0x6060, 0, 1, 1, 0x06090030U},            // only profile velocity
      {0x605A, 0, 3, 2, 0x06090030U},            // a quick stop option not implemented
      {0x6083, 0, 0, 4, 0x06090032U},            // a zero acceleration
      {0x1600, 0, 0, 1, 0x08000022U},            // mapping while the PDO is valid
      {0x1400, 1, 0x80000201U, 4, 0x06090030U},  // another COB-ID
      {0x1800, 2, 0xFF, 1, 0x06090030U},         // event-driven TPDO: not implemented
  };
  std::uint64_t aborts = 0;
  for (const auto& c : cases) {
    const SdoResult r = download(c.index, c.sub, c.value, c.size);
    EXPECT_EQ(r.state, SdoState::Aborted) << std::hex << c.index;
    EXPECT_EQ(r.abort_code, c.code) << r.message;
    ++aborts;
  }
  EXPECT_EQ(upload(0x2000, 0).abort_code, 0x06020000U);
  EXPECT_EQ(upload(0x1018, 9).abort_code, 0x06090011U);
  aborts += 2;
  // The fixed PDO mapping: written again it is accepted, changed it is refused.
  ASSERT_EQ(download(0x1400, 1, 0x80000000U | (0x200 + kNode), 4).state, SdoState::Done);
  EXPECT_EQ(download(0x1600, 1, 0x60400010U, 4).abort_code, 0x08000022U);  // sub 0 first
  ASSERT_EQ(download(0x1600, 0, 0, 1).state, SdoState::Done);
  EXPECT_EQ(download(0x1600, 1, 0x60410010U, 4).abort_code, 0x06040041U);
  EXPECT_EQ(download(0x1600, 0, 3, 1).abort_code, 0x06040042U);
  EXPECT_EQ(download(0x1600, 0, 1, 1).abort_code, 0x06040041U);
  aborts += 4;
  EXPECT_EQ(download(0x1600, 0, 2, 1).state, SdoState::Done);
  EXPECT_EQ(drive_.counters().sdo_aborts_sent, aborts);
}

TEST_F(DriveEmulatorTest, GoesThroughThePowerStatesToOperationEnabled) {
  bring_up();
  const std::vector<State> seen = drive_to(cia402::Goal::Enabled);
  const std::vector<State> want = {State::SwitchOnDisabled, State::ReadyToSwitchOn,
                                   State::SwitchedOn, State::OperationEnabled};
  EXPECT_EQ(seen, want);
  EXPECT_TRUE(psm_.at_goal());
  EXPECT_EQ(cia402::decode_statusword(static_cast<std::uint16_t>(upload(0x6041, 0).value)),
            State::OperationEnabled);
  EXPECT_EQ(drive_.counters().state_transitions, 4U);  // power-on's Not ready -> disabled too
  const std::vector<State> back = drive_to(cia402::Goal::Disabled);
  EXPECT_EQ(back.back(), State::SwitchOnDisabled);
}

TEST_F(DriveEmulatorTest, RampsToTheTargetAndFollowsItFirstOrder) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  ASSERT_EQ(drive_.state(), State::OperationEnabled);
  // 10 rad/s at 25 rad/s^2 takes 0.4 s of ramp, the 20 ms velocity loop lags it by ~tau.
  double at_200ms = 0.0;
  Seen s;
  for (int i = 0; i < 70; ++i) {
    s = cycle(cia402::kCwEnableOperation, 10.0);
    if (i == 19) at_200ms = drive_.wheel_speed_radps();
    if (i < 30) EXPECT_EQ(s.sw & cia402::kSwTargetReached, 0) << i;
  }
  EXPECT_LT(at_200ms, 25.0 * 0.2);                 // the ramp limits it
  EXPECT_GT(at_200ms, 25.0 * (0.2 - 0.02) - 0.3);  // and the loop follows it a tau behind
  EXPECT_NEAR(drive_.wheel_speed_radps(), 10.0, 0.01);
  EXPECT_NEAR(cia402::to_wheel_radps(s.velocity, units()), 10.0, 0.01);
  EXPECT_NE(s.sw & cia402::kSwTargetReached, 0);
  // Down again on the deceleration ramp (25 rad/s^2): not stopped before 0.3 s.
  for (int i = 0; i < 30; ++i) cycle(cia402::kCwEnableOperation, 0.0);
  EXPECT_GT(drive_.wheel_speed_radps(), 0.5);
  for (int i = 0; i < 30; ++i) s = cycle(cia402::kCwEnableOperation, 0.0);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  EXPECT_EQ(s.velocity, 0);
}

TEST_F(DriveEmulatorTest, HaltBitDeceleratesToZeroAndReleasesAgain) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, -8.0);
  EXPECT_NEAR(drive_.wheel_speed_radps(), -8.0, 0.01);
  Seen s;
  for (int i = 0; i < 60; ++i) s = cycle(cia402::kCwEnableOperation | cia402::kCwHalt, -8.0);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  EXPECT_EQ(cia402::decode_statusword(s.sw), State::OperationEnabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, -8.0);
  EXPECT_NEAR(drive_.wheel_speed_radps(), -8.0, 0.01);
}

TEST_F(DriveEmulatorTest, QuickStopRampsToZeroAndHolds) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  ASSERT_NEAR(drive_.wheel_speed_radps(), 10.0, 0.01);
  // 10 rad/s at the quick stop's 50 rad/s^2: 0.2 s; still moving at 0.1 s.
  for (int i = 0; i < 10; ++i) cycle(cia402::kCwQuickStop, 10.0);
  EXPECT_EQ(drive_.state(), State::QuickStopActive);
  EXPECT_GT(drive_.wheel_speed_radps(), 2.0);
  EXPECT_LT(drive_.wheel_speed_radps(), 7.0);
  Seen s;
  for (int i = 0; i < 100; ++i) s = cycle(cia402::kCwQuickStop, 10.0);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  EXPECT_EQ(cia402::decode_statusword(s.sw), State::QuickStopActive);  // option 6: stays
  EXPECT_NE(s.sw & cia402::kSwTargetReached, 0);
  EXPECT_EQ(s.velocity, 0);
}

TEST_F(DriveEmulatorTest, StopsTheWheelOnItsOwnWhenTheMasterHeartbeatStops) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  ASSERT_NEAR(drive_.wheel_speed_radps(), 10.0, 0.01);
  const std::size_t from = rx_.size();
  // The master dies: no heartbeat, no RPDO, no SYNC. The consumer time is 150 ms.
  run(140 * kMs);
  EXPECT_NEAR(drive_.wheel_speed_radps(), 10.0, 0.01);  // not yet
  EXPECT_FALSE(drive_.master_heartbeat_lost());
  run(20 * kMs);
  EXPECT_TRUE(drive_.master_heartbeat_lost());
  EXPECT_EQ(drive_.state(), State::FaultReactionActive);
  run(500 * kMs);  // the quick stop ramp: 0.2 s, then the loop settles (~10 tau)
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  EXPECT_EQ(drive_.state(), State::Fault);
  EXPECT_EQ(drive_.counters().master_heartbeat_losses, 1U);
  const auto e = emcys(from);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].error_code, kEmcyHeartbeatLost);
  EXPECT_EQ(e[0].error_register & 0x11, 0x11);  // generic and communication
  // NMT falls back to Pre-operational, as its heartbeat says.
  const auto hb = frames(0x700 + kNode, from);
  ASSERT_FALSE(hb.empty());
  EXPECT_EQ(hb.back().data[0], 0x7F);
  EXPECT_EQ(upload(0x603F, 0).value, kEmcyHeartbeatLost);
}

TEST_F(DriveEmulatorTest, AppliesTheRpdoAtTheNextSyncOnly) {
  bring_up();
  master().send(canopen::rpdo1(kNode, cia402::kCwShutdown, 0));
  tick();
  EXPECT_EQ(drive_.state(), State::SwitchOnDisabled);  // received, not yet applied
  EXPECT_EQ(drive_.counters().rpdos_applied, 0U);
  master().send(canopen::sync_frame());
  tick();
  EXPECT_EQ(drive_.state(), State::ReadyToSwitchOn);
  EXPECT_EQ(drive_.counters().rpdos_applied, 1U);
}

TEST_F(DriveEmulatorTest, LeavingOperationalQuickStopsAMovingWheel) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  master().send(canopen::nmt(canopen::NmtCommand::EnterPreOperational, kNode));
  for (int i = 0; i < 50; ++i) {  // the master lives on, without PDOs
    master().send(canopen::heartbeat(kMaster, canopen::NmtState::PreOperational));
    tick();
  }
  EXPECT_EQ(drive_.state(), State::QuickStopActive);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
}

TEST_F(DriveEmulatorTest, HoldsStillWithoutProfileVelocityMode) {
  tick();
  master().send(canopen::nmt(canopen::NmtCommand::Start, kNode));  // no bring-up: 0x6060 = 0
  tick();
  drive_to(cia402::Goal::Enabled);
  ASSERT_EQ(drive_.state(), State::OperationEnabled);
  for (int i = 0; i < 50; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  EXPECT_EQ(upload(0x6061, 0).value, 0U);
}

TEST_F(DriveEmulatorTest, ProducesHeartbeatsAtThePeriodOf0x1017) {
  bring_up();  // 0x1017 = 50 ms
  const std::size_t from = rx_.size();
  run(1000 * kMs, kMs);
  const auto hb = frames(0x700 + kNode, from);
  EXPECT_EQ(hb.size(), 20U);
  for (const CanFrame& f : hb) EXPECT_EQ(f.data[0], 0x05);
}

TEST_F(DriveEmulatorTest, HonoursTheTpdoTransmissionType) {
  bring_up();
  ASSERT_EQ(download(0x1800, 2, 3, 1).state, SdoState::Done);  // TPDO1 every 3rd SYNC
  int tpdo1 = 0, tpdo2 = 0;
  for (int i = 0; i < 9; ++i) {
    const Seen s = cycle(0, 0.0);
    tpdo1 += s.tpdo1;
    tpdo2 += s.tpdo2;
  }
  EXPECT_EQ(tpdo1, 3);
  EXPECT_EQ(tpdo2, 9);
}

class DriveEmulatorWrapTest : public DriveEmulatorTest {
 protected:
  DriveEmulatorWrapTest() : DriveEmulatorTest(std::int64_t(INT_MAX) - 20000) {}
};

TEST_F(DriveEmulatorWrapTest, PositionActualIntegratesTheSpeedAndWraps) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  cia402::PositionUnwrapper odometry;
  bool wrapped = false;
  std::int32_t last = 0;
  for (int i = 0; i < 100; ++i) {
    const Seen s = cycle(cia402::kCwEnableOperation, 5.0);  // ~32600 counts/s
    ASSERT_TRUE(s.tpdo2);
    if (i > 0 && s.position < last) wrapped = true;
    last = s.position;
    odometry.add(s.position);
  }
  EXPECT_TRUE(wrapped);
  EXPECT_LT(last, 0);
  // The odometry across the wrap is the drive's own wheel angle, to a count.
  const double rad_per_count = 2.0 * 3.141592653589793 / (4096.0 * 10.0);
  EXPECT_GT(odometry.wheel_rad(units()), 1.0);
  // TPDO2 is sampled at the SYNC, before the step's motion: one step behind the model.
  const double sampled = drive_.wheel_position_rad() - drive_.wheel_speed_radps() * 0.01;
  EXPECT_NEAR(odometry.wheel_rad(units()), sampled, 2.0 * rad_per_count);
}

// ---- fault injection -------------------------------------------------------------------------

TEST_F(DriveEmulatorTest, HeartbeatSilenceStopsOnlyHeartbeatsBusSilenceEverything) {
  bring_up();
  drive_.set_silence(DriveEmulator::Silence::Heartbeat);
  std::size_t from = rx_.size();
  int tpdos = 0;
  for (int i = 0; i < 20; ++i) tpdos += cycle(0, 0.0).tpdo1;
  EXPECT_TRUE(frames(0x700 + kNode, from).empty());
  EXPECT_EQ(tpdos, 20);
  EXPECT_EQ(upload(0x1000, 0).state, SdoState::Done);

  drive_.set_silence(DriveEmulator::Silence::Bus);
  from = rx_.size();
  for (int i = 0; i < 20; ++i) cycle(0, 0.0);
  EXPECT_EQ(upload(0x1000, 0).state, SdoState::TimedOut);
  EXPECT_EQ(rx_.size(), from);  // nothing at all
  EXPECT_GT(drive_.counters().frames_silenced, 40U);
  // It still listens and acts: an NMT command reaches it.
  master().send(canopen::nmt(canopen::NmtCommand::Stop, kNode));
  tick();
  EXPECT_EQ(drive_.nmt_state(), canopen::NmtState::Stopped);
  drive_.set_silence(DriveEmulator::Silence::None);
  tick(50 * kMs);
  EXPECT_EQ(frames(0x700 + kNode, from).size(), 1U);
  EXPECT_STREQ(silence_name(DriveEmulator::Silence::Bus), "bus");
}

TEST_F(DriveEmulatorTest, InjectedFaultSendsEmcyStopsAndResetsOnARisingEdge) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  for (int i = 0; i < 60; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  std::size_t from = rx_.size();
  drive_.inject_fault(0x2310);
  for (int i = 0; i < 40; ++i) cycle(cia402::kCwEnableOperation, 10.0);
  EXPECT_EQ(drive_.state(), State::Fault);
  EXPECT_EQ(drive_.wheel_speed_radps(), 0.0);
  auto e = emcys(from);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].error_code, 0x2310);
  EXPECT_EQ(e[0].error_register, 0x03);  // generic + current
  // Bit 7 held high is one edge only; the master's reset brings it to Switch on disabled.
  cycle(cia402::kCwFaultReset, 0.0);
  EXPECT_EQ(drive_.state(), State::SwitchOnDisabled);
  e = emcys(from);
  ASSERT_EQ(e.size(), 2U);
  EXPECT_EQ(e[1].error_code, kEmcyErrorReset);

  // A persistent fault refuses resets until it is cleared.
  drive_.inject_fault(0x4310, true);
  cycle(0, 0.0);
  cycle(cia402::kCwFaultReset, 0.0);
  EXPECT_EQ(drive_.state(), State::Fault);
  drive_.clear_persistent_fault();
  cycle(cia402::kCwFaultReset, 0.0);  // still high: no edge
  EXPECT_EQ(drive_.state(), State::Fault);
  cycle(0, 0.0);
  cycle(cia402::kCwFaultReset, 0.0);
  EXPECT_EQ(drive_.state(), State::SwitchOnDisabled);
  EXPECT_EQ(drive_.counters().fault_resets, 2U);
}

TEST_F(DriveEmulatorTest, RefusesToEnableStuckInTheNamedState) {
  bring_up();
  drive_.refuse_enable(State::SwitchedOn);
  drive_to(cia402::Goal::Enabled, 0.0, 20);
  EXPECT_FALSE(psm_.at_goal());
  EXPECT_EQ(psm_.state(), State::SwitchedOn);
  EXPECT_EQ(psm_.awaiting(), State::OperationEnabled);
  EXPECT_GT(drive_.counters().transitions_refused, 10U);
  drive_.refuse_enable(State::Unknown);
  drive_to(cia402::Goal::Enabled);
  EXPECT_TRUE(psm_.at_goal());

  drive_to(cia402::Goal::Disabled);
  drive_.refuse_enable(State::SwitchOnDisabled);
  drive_to(cia402::Goal::Enabled);
  EXPECT_EQ(psm_.state(), State::SwitchOnDisabled);
  EXPECT_EQ(psm_.awaiting(), State::ReadyToSwitchOn);

  // Stuck before Switch on disabled: the statusword reports Not ready to switch on.
  drive_.refuse_enable(State::NotReadyToSwitchOn);
  drive_.power_cycle();
  tick();
  EXPECT_EQ(cia402::decode_statusword(drive_.statusword()), State::NotReadyToSwitchOn);
}

TEST_F(DriveEmulatorTest, AbortsInjectedSdoAccessesWithTheGivenCode) {
  tick();
  ASSERT_TRUE(drive_.inject_sdo_abort(0x6060, 0, 0x08000021U));
  SdoResult r = download(0x6060, 0, 3, 1);
  EXPECT_EQ(r.state, SdoState::Aborted);
  EXPECT_EQ(r.abort_code, 0x08000021U);
  EXPECT_EQ(upload(0x6060, 0).abort_code, 0x08000021U);
  EXPECT_EQ(download(0x6083, 0, 100, 4).state, SdoState::Done);  // others unaffected
  drive_.clear_sdo_aborts();
  EXPECT_EQ(download(0x6060, 0, 3, 1).state, SdoState::Done);
  ASSERT_TRUE(drive_.inject_sdo_abort(0x1A00, SdoServer::kAnySubindex, 0x06040043U));
  EXPECT_EQ(upload(0x1A00, 2).abort_code, 0x06040043U);
}

TEST_F(DriveEmulatorTest, MixesCorruptAndUnknownFramesIntoItsOutput) {
  bring_up();
  drive_.inject_corrupt_frames(3);
  drive_.inject_unknown_frames(2);
  const std::size_t from = rx_.size();
  int good = 0;
  for (int i = 0; i < 5; ++i) good += cycle(0, 0.0).tpdo1;
  EXPECT_EQ(good, 2);
  const auto t1 = frames(0x180 + kNode, from);
  ASSERT_EQ(t1.size(), 5U);
  EXPECT_EQ(t1[0].len, 5);
  EXPECT_EQ(t1[3].len, 6);
  const auto unknown = frames(0x380 + kNode, from);
  EXPECT_EQ(unknown.size(), 2U);
  EXPECT_EQ(drive_.counters().frames_injected, 3U * 2U + 2U);
}

TEST_F(DriveEmulatorTest, CountsFramesNotForItAndMalformedOnesWithoutActing) {
  bring_up();
  drive_to(cia402::Goal::Enabled);
  const auto before = drive_.counters();
  CanFrame other_sdo;
  other_sdo.id = 0x600 + kNode + 1;
  other_sdo.len = 8;
  other_sdo.data[0] = 0x40;
  master().send(other_sdo);
  master().send(canopen::rpdo1(kNode + 1, cia402::kCwQuickStop, 0));
  CanFrame short_rpdo = canopen::rpdo1(kNode, cia402::kCwQuickStop, 0);
  short_rpdo.len = 5;
  master().send(short_rpdo);
  CanFrame short_sdo = other_sdo;
  short_sdo.id = 0x600 + kNode;
  short_sdo.len = 4;
  master().send(short_sdo);
  const std::size_t from = rx_.size();
  cycle(cia402::kCwEnableOperation, 0.0);
  EXPECT_EQ(drive_.state(), State::OperationEnabled);
  EXPECT_EQ(drive_.counters().frames_unknown - before.frames_unknown, 2U);
  EXPECT_EQ(drive_.counters().frames_malformed - before.frames_malformed, 2U);
  EXPECT_TRUE(frames(0x580 + kNode, from).empty());  // no answer to either SDO
  const auto e = emcys(from);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].error_code, kEmcyPdoLength);
}

}  // namespace
}  // namespace carril::sim
