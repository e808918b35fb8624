#include "hal/canopen/Cia402.hpp"

#include <cmath>
#include <numbers>

namespace carril::hal::cia402 {

const char* state_name(State s) {
  switch (s) {
    case State::NotReadyToSwitchOn:
      return "Not ready to switch on";
    case State::SwitchOnDisabled:
      return "Switch on disabled";
    case State::ReadyToSwitchOn:
      return "Ready to switch on";
    case State::SwitchedOn:
      return "Switched on";
    case State::OperationEnabled:
      return "Operation enabled";
    case State::QuickStopActive:
      return "Quick stop active";
    case State::FaultReactionActive:
      return "Fault reaction active";
    case State::Fault:
      return "Fault";
    case State::Unknown:
      break;
  }
  return "unknown (statusword matches no state)";
}

State decode_statusword(std::uint16_t sw) {
  // CiA 402 table 6.3.1: the states that leave bit 5 (quick stop) open use mask 0x4F, the
  // others 0x6F.
  switch (sw & 0x4FU) {
    case 0x00:
      return State::NotReadyToSwitchOn;
    case 0x40:
      return State::SwitchOnDisabled;
    case 0x0F:
      return State::FaultReactionActive;
    case 0x08:
      return State::Fault;
    default:
      break;
  }
  switch (sw & 0x6FU) {
    case 0x21:
      return State::ReadyToSwitchOn;
    case 0x23:
      return State::SwitchedOn;
    case 0x27:
      return State::OperationEnabled;
    case 0x07:
      return State::QuickStopActive;
    default:
      break;
  }
  return State::Unknown;
}

std::uint16_t PowerStateMachine::step(std::uint16_t sw, Goal goal, bool reset_faults) {
  state_ = decode_statusword(sw);
  at_goal_ = false;
  std::uint16_t cw = kCwDisableVoltage;
  State next = state_;
  if (state_ == State::Fault || state_ == State::FaultReactionActive) {
    // A fault reset is the rising edge of bit 7: low first if the last controlword had it high.
    if (state_ == State::Fault && reset_faults) {
      if ((cw_ & kCwFaultReset) == 0) {
        cw = kCwFaultReset;
        ++resets_;
        next = State::SwitchOnDisabled;
      }
    }
    // A drive in fault has no torque: stopped, which is what a quick stop wants.
    at_goal_ = goal == Goal::QuickStop;
    awaiting_ = next;
    cw_ = cw;
    return cw;
  }
  switch (goal) {
    case Goal::Enabled:
      switch (state_) {
        case State::SwitchOnDisabled:
          cw = kCwShutdown;
          next = State::ReadyToSwitchOn;
          break;
        case State::ReadyToSwitchOn:
          cw = kCwSwitchOn;
          next = State::SwitchedOn;
          break;
        case State::SwitchedOn:
        case State::OperationEnabled:
          cw = kCwEnableOperation;
          next = State::OperationEnabled;
          at_goal_ = state_ == State::OperationEnabled;
          break;
        default:  // not ready (the drive moves on by itself), quick stop, unknown: start over
          cw = kCwDisableVoltage;
          next = State::SwitchOnDisabled;
          break;
      }
      break;
    case Goal::Disabled:
      cw = kCwDisableVoltage;
      next = State::SwitchOnDisabled;
      at_goal_ = state_ == State::SwitchOnDisabled || state_ == State::NotReadyToSwitchOn;
      break;
    case Goal::QuickStop:
      cw = kCwQuickStop;
      next = state_ == State::OperationEnabled ? State::QuickStopActive : state_;
      // Only Operation enabled drives the motor; every other state is already without torque.
      at_goal_ = state_ != State::OperationEnabled;
      break;
  }
  awaiting_ = next;
  cw_ = cw;
  return cw;
}

std::int32_t to_counts_per_s(double wheel_radps, const DriveUnits& u) {
  const double c = wheel_radps * u.gear_ratio * u.counts_per_rev / (2.0 * std::numbers::pi);
  if (!std::isfinite(c)) return 0;  // a NaN setpoint must not turn into a speed
  if (c >= 2147483647.0) return 2147483647;
  if (c <= -2147483648.0) return -2147483647 - 1;
  return static_cast<std::int32_t>(std::lround(c));
}

double to_wheel_radps(std::int32_t counts_per_s, const DriveUnits& u) {
  return double(counts_per_s) * 2.0 * std::numbers::pi / (u.counts_per_rev * u.gear_ratio);
}

void PositionUnwrapper::add(std::int32_t p) {
  if (primed_) {
    // The difference modulo 2^32, as a signed step: right across a wrap in either direction.
    const auto step = static_cast<std::int32_t>(static_cast<std::uint32_t>(p) -
                                                static_cast<std::uint32_t>(last_));
    total_ += step;
  }
  primed_ = true;
  last_ = p;
}

double PositionUnwrapper::wheel_rad(const DriveUnits& u) const {
  return double(total_) * 2.0 * std::numbers::pi / (u.counts_per_rev * u.gear_ratio);
}

}  // namespace carril::hal::cia402
