// CiA 402 from the master's side: statusword decoding, the controlword sequence toward a goal
// (against a small model of a drive's power state machine), the fault reset edge, the halt bit,
// and wheel units <-> drive counts with the 32-bit position counter's wrap.
#include "hal/canopen/Cia402.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace carril::hal::cia402 {
namespace {

// Canonical statuswords of each state (CiA 402 table 6.3.1), with unrelated bits set too.
struct Sample {
  std::uint16_t sw;
  State state;
};
const Sample kSamples[] = {
    {0x0000, State::NotReadyToSwitchOn},  {0x0040, State::SwitchOnDisabled},
    {0x0021, State::ReadyToSwitchOn},     {0x0023, State::SwitchedOn},
    {0x0027, State::OperationEnabled},    {0x0007, State::QuickStopActive},
    {0x000F, State::FaultReactionActive}, {0x0008, State::Fault},
};

TEST(Cia402Statusword, DecodesEveryStateWhateverTheOtherBitsSay) {
  const std::uint16_t others[] = {0x0000, kSwVoltageEnabled, kSwWarning | kSwRemote,
                                  kSwTargetReached | kSwRemote | kSwVoltageEnabled, 0xFF00};
  for (const Sample& s : kSamples) {
    for (const std::uint16_t o : others) {
      const auto sw = static_cast<std::uint16_t>(s.sw | o);
      EXPECT_EQ(decode_statusword(sw), s.state) << std::hex << sw << " " << state_name(s.state);
    }
  }
  // Bit 5 is open in the 0x4F states: Switch on disabled with bit 5 set is still that state.
  EXPECT_EQ(decode_statusword(0x0060), State::SwitchOnDisabled);
  EXPECT_EQ(decode_statusword(0x0028), State::Fault);
  EXPECT_EQ(decode_statusword(0x0001), State::Unknown);
  EXPECT_STREQ(state_name(State::SwitchOnDisabled), "Switch on disabled");
}

// A drive's side of the power state machine, enough to answer the master: transitions of CiA
// 402 figure 6.3.1 on the controlword, one per period.
struct ModelDrive {
  State s = State::SwitchOnDisabled;
  std::uint16_t last_cw = 0;
  bool refuse_switch_on = false;  // stays Ready to switch on (e.g. no DC link voltage)
  std::uint16_t sw() const {
    for (const Sample& x : kSamples) {
      if (x.state == s) return x.sw;
    }
    return 0x0001;
  }
  void apply(std::uint16_t cw) {
    ASSERT_EQ(cw & kCwHalt, 0) << "halt bit set";
    const bool edge7 = (cw & 0x80) != 0 && (last_cw & 0x80) == 0;
    last_cw = cw;
    if (s == State::Fault) {
      if (edge7) s = State::SwitchOnDisabled;
      return;
    }
    const std::uint16_t c = cw & 0x0F;
    if ((c & 0x02) == 0) {  // disable voltage
      s = State::SwitchOnDisabled;
    } else if ((c & 0x04) == 0) {  // quick stop
      s = s == State::OperationEnabled ? State::QuickStopActive : State::SwitchOnDisabled;
    } else if (c == 0x06) {
      s = State::ReadyToSwitchOn;
    } else if (c == 0x07 && s == State::ReadyToSwitchOn && !refuse_switch_on) {
      s = State::SwitchedOn;
    } else if (c == 0x07 && s == State::OperationEnabled) {
      s = State::SwitchedOn;
    } else if (c == 0x0F && (s == State::SwitchedOn || s == State::OperationEnabled)) {
      s = State::OperationEnabled;
    }
  }
};

TEST(Cia402PowerStateMachine, EnablesInThreePeriodsFromSwitchOnDisabled) {
  ModelDrive d;
  PowerStateMachine m;
  std::vector<std::uint16_t> sent;
  for (int i = 0; i < 5 && !m.at_goal(); ++i) {
    const std::uint16_t cw = m.step(d.sw(), Goal::Enabled);
    sent.push_back(cw);
    d.apply(cw);
  }
  EXPECT_EQ(sent, (std::vector<std::uint16_t>{kCwShutdown, kCwSwitchOn, kCwEnableOperation,
                                              kCwEnableOperation}));
  EXPECT_TRUE(m.at_goal());
  EXPECT_EQ(d.s, State::OperationEnabled);
}

TEST(Cia402PowerStateMachine, AStuckBringUpNamesTheStateAndWhatItWaitsFor) {
  ModelDrive d;
  d.refuse_switch_on = true;
  PowerStateMachine m;
  for (int i = 0; i < 20; ++i) d.apply(m.step(d.sw(), Goal::Enabled));
  EXPECT_FALSE(m.at_goal());
  EXPECT_EQ(m.state(), State::ReadyToSwitchOn);
  EXPECT_EQ(m.awaiting(), State::SwitchedOn);
  EXPECT_EQ(m.controlword(), kCwSwitchOn);
}

TEST(Cia402PowerStateMachine, QuickStopThenDisable) {
  ModelDrive d;
  PowerStateMachine m;
  for (int i = 0; i < 4; ++i) d.apply(m.step(d.sw(), Goal::Enabled));
  ASSERT_EQ(d.s, State::OperationEnabled);
  d.apply(m.step(d.sw(), Goal::QuickStop));
  EXPECT_EQ(m.controlword(), kCwQuickStop);
  EXPECT_EQ(d.s, State::QuickStopActive);
  m.step(d.sw(), Goal::QuickStop);
  EXPECT_TRUE(m.at_goal());
  d.apply(m.step(d.sw(), Goal::Disabled));
  m.step(d.sw(), Goal::Disabled);
  EXPECT_EQ(d.s, State::SwitchOnDisabled);
  EXPECT_TRUE(m.at_goal());
}

TEST(Cia402PowerStateMachine, FaultResetIsARisingEdgeOfBit7AndOnlyWhenAsked) {
  ModelDrive d;
  d.s = State::Fault;
  PowerStateMachine m;
  for (int i = 0; i < 3; ++i) d.apply(m.step(d.sw(), Goal::Enabled));  // not asked: stays
  EXPECT_EQ(d.s, State::Fault);
  EXPECT_EQ(m.fault_resets(), 0U);
  d.apply(m.step(d.sw(), Goal::Enabled, true));
  EXPECT_EQ(m.controlword(), kCwFaultReset);
  EXPECT_EQ(m.fault_resets(), 1U);
  EXPECT_EQ(d.s, State::SwitchOnDisabled);
  for (int i = 0; i < 4; ++i) d.apply(m.step(d.sw(), Goal::Enabled));
  EXPECT_EQ(d.s, State::OperationEnabled);
}

TEST(Cia402PowerStateMachine, AFaultThatStaysGetsAFreshEdgeEachTime) {
  PowerStateMachine m;
  std::vector<std::uint16_t> sent;
  for (int i = 0; i < 4; ++i) sent.push_back(m.step(0x0008, Goal::Enabled, true));
  // High, low, high, low: every high is a rising edge.
  EXPECT_EQ(sent, (std::vector<std::uint16_t>{0x0080, 0x0000, 0x0080, 0x0000}));
  EXPECT_EQ(m.fault_resets(), 2U);
}

TEST(Cia402PowerStateMachine, NeverSetsTheHaltBit) {
  for (const Sample& s : kSamples) {
    for (const Goal g : {Goal::Disabled, Goal::Enabled, Goal::QuickStop}) {
      PowerStateMachine m;
      for (const bool reset : {false, true}) {
        EXPECT_EQ(m.step(s.sw, g, reset) & kCwHalt, 0) << state_name(s.state);
      }
    }
  }
}

TEST(Cia402Units, WheelSpeedToCountsAndBack) {
  const DriveUnits u{4096.0, 20.0};  // 4096-count encoder, 20:1 gearbox
  // One wheel revolution per second = 20 motor revolutions = 81,920 counts/s.
  EXPECT_EQ(to_counts_per_s(2.0 * std::numbers::pi, u), 81920);
  EXPECT_EQ(to_counts_per_s(-2.0 * std::numbers::pi, u), -81920);
  EXPECT_NEAR(to_wheel_radps(81920, u), 2.0 * std::numbers::pi, 1e-12);
  for (const double w : {0.0, 0.1, -3.7, 12.0}) {
    EXPECT_NEAR(to_wheel_radps(to_counts_per_s(w, u), u), w, 2.0 * std::numbers::pi / 81920.0);
  }
  EXPECT_EQ(to_counts_per_s(1e12, u), std::numeric_limits<std::int32_t>::max());
  EXPECT_EQ(to_counts_per_s(-1e12, u), std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(to_counts_per_s(std::numeric_limits<double>::quiet_NaN(), u), 0);
}

TEST(Cia402Units, PositionAcrossThe32BitWrapInBothDirections) {
  const DriveUnits u{4096.0, 1.0};
  PositionUnwrapper p;
  const std::int32_t max = std::numeric_limits<std::int32_t>::max();
  p.add(max - 100);
  p.add(max);
  p.add(std::numeric_limits<std::int32_t>::min() + 99);  // +100 more: wrapped
  EXPECT_EQ(p.counts(), 200);
  p.add(max - 100);  // back again across the wrap
  EXPECT_EQ(p.counts(), 0);
  p.add(max - 100 - 4096);
  EXPECT_EQ(p.counts(), -4096);
  EXPECT_NEAR(p.wheel_rad(u), -2.0 * std::numbers::pi, 1e-12);
}

}  // namespace
}  // namespace carril::hal::cia402
