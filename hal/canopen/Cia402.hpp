#pragma once
// CiA 402 (drives and motion control) as seen from the master: the power state machine decoded
// from the statusword (0x6041), the controlword (0x6040) that moves a drive toward the state the
// firmware wants, and the conversion between wheel units at the HAL (rad, rad/s) and the drive's
// units on the bus (encoder counts of the motor shaft). Pure logic: no bus, no clock, no heap.
#include <cstdint>

#include "hal/Types.hpp"

namespace carril::hal::cia402 {

// The power state machine's states (CiA 402, 6.3.2), plus Unknown for a statusword that matches
// none of them.
enum class State : std::uint8_t {
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
  Unknown,
};

// The state's name as CiA 402 writes it, e.g. "Switch on disabled".
const char* state_name(State s);

// The state a statusword reports (bits 0-3, 5 and 6; the others are ignored).
State decode_statusword(std::uint16_t statusword);

// Statusword bits beyond the state.
constexpr std::uint16_t kSwVoltageEnabled = 1U << 4;
constexpr std::uint16_t kSwWarning = 1U << 7;
constexpr std::uint16_t kSwRemote = 1U << 9;
constexpr std::uint16_t kSwTargetReached = 1U << 10;

// Controlword commands (CiA 402, table 6.3.2). The halt bit (8) is never set by these: a drive
// left halted ignores its velocity target (ros2_canopen #234).
constexpr std::uint16_t kCwShutdown = 0x0006;          // -> Ready to switch on
constexpr std::uint16_t kCwSwitchOn = 0x0007;          // -> Switched on
constexpr std::uint16_t kCwEnableOperation = 0x000F;   // -> Operation enabled
constexpr std::uint16_t kCwDisableVoltage = 0x0000;    // -> Switch on disabled
constexpr std::uint16_t kCwQuickStop = 0x0002;         // -> Quick stop active
constexpr std::uint16_t kCwDisableOperation = 0x0007;  // Operation enabled -> Switched on
constexpr std::uint16_t kCwFaultReset =
    0x0080;  // rising edge of bit 7: Fault -> Switch on disabled
constexpr std::uint16_t kCwHalt = 1U << 8;

// What the firmware wants of a drive.
enum class Goal : std::uint8_t { Disabled, Enabled, QuickStop };

// Drives one drive's power state machine toward a goal, one controlword per control period, and
// says what it is waiting for, so a bring-up that does not finish names the state the drive is
// stuck in and the transition it was asked for.
class PowerStateMachine {
 public:
  // One period: the drive reported `sw`; returns the controlword to send. `reset_faults` asks for
  // one fault reset (a rising edge of bit 7 over two periods) while the drive is in Fault.
  std::uint16_t step(std::uint16_t sw, Goal goal, bool reset_faults = false);
  State state() const { return state_; }
  // The state the last controlword asks the drive to reach (the current one when none).
  State awaiting() const { return awaiting_; }
  // The last controlword sent.
  std::uint16_t controlword() const { return cw_; }
  // The goal is reached (Operation enabled for Enabled, Switch on disabled or Ready to switch on
  // for Disabled, Quick stop active or a stopped drive for QuickStop).
  bool at_goal() const { return at_goal_; }
  // Fault resets sent (rising edges of bit 7).
  std::uint32_t fault_resets() const { return resets_; }

 private:
  State state_ = State::Unknown;
  State awaiting_ = State::Unknown;
  std::uint16_t cw_ = kCwDisableVoltage;
  bool at_goal_ = false;
  std::uint32_t resets_ = 0;
};

// Drive units: the motor's encoder counts, through a gearbox, at the wheel.
struct DriveUnits {
  double counts_per_rev = 4096.0;  // encoder counts per motor revolution
  double gear_ratio = 1.0;         // motor revolutions per wheel revolution
};

// Wheel speed [rad/s] to the drive's target velocity 0x60FF [counts/s], rounded, saturated to
// int32.
std::int32_t to_counts_per_s(double wheel_radps, const DriveUnits& u);
// The drive's velocity actual 0x606C [counts/s] to wheel speed [rad/s].
double to_wheel_radps(std::int32_t counts_per_s, const DriveUnits& u);

// Position actual 0x6064 is a 32-bit counter that wraps; this accumulates it into a wheel angle
// [rad] that does not (a wheel at 3000 counts/ms wraps a 32-bit counter in 20 minutes).
class PositionUnwrapper {
 public:
  // Feeds one reading; the first only latches it.
  void add(std::int32_t position_counts);
  // Takes the next readings from `position_counts` without counting the step to it (a reading
  // that jumped further than the wheel can turn).
  void rebase(std::int32_t position_counts) {
    primed_ = true;
    last_ = position_counts;
  }
  // Counts since the first reading, across wraps.
  std::int64_t counts() const { return total_; }
  // Wheel angle since the first reading [rad].
  double wheel_rad(const DriveUnits& u) const;

 private:
  bool primed_ = false;
  std::int32_t last_ = 0;
  std::int64_t total_ = 0;
};

}  // namespace carril::hal::cia402
