#include "host_sim/drives/DriveEmulator.hpp"

#include <cmath>
#include <numbers>

namespace carril::sim {

namespace canopen = hal::canopen;
using hal::CanFrame;
using State = DriveEmulator::State;
using NmtState = DriveEmulator::NmtState;

namespace {

constexpr double kStoppedCps = 0.5;  // below this [counts/s] with no demand, the motor is still

// CiA 402 controlword commands (table 6.3.2), as the drive decodes them.
enum class Command : std::uint8_t { DisableVoltage, QuickStop, Shutdown, SwitchOn, Enable, None };

Command decode_command(std::uint16_t cw) {
  if ((cw & 0x80U) != 0) return Command::None;  // a fault reset outside Fault does nothing
  if ((cw & 0x02U) == 0) return Command::DisableVoltage;
  if ((cw & 0x04U) == 0) return Command::QuickStop;
  if ((cw & 0x01U) == 0) return Command::Shutdown;
  if ((cw & 0x08U) == 0) return Command::SwitchOn;  // also "disable operation"
  return Command::Enable;
}

// One ramp step from `from` toward `to` [counts/s]: magnitude grows at `accel`, shrinks at
// `decel` [counts/s per step]; a change of sign first stops at zero.
double ramp(double from, double to, double accel, double decel) {
  if (from == to) return to;
  if ((from > 0.0 && to < 0.0) || (from < 0.0 && to > 0.0)) to = 0.0;
  const bool growing = std::fabs(to) > std::fabs(from);
  const double step = growing ? accel : decel;
  if (to > from) return from + step >= to ? to : from + step;
  return from - step <= to ? to : from - step;
}

// Error register 0x1001 bits for an error code (CiA 301, 7.5.2.2).
std::uint8_t error_register(std::uint16_t code) {
  if (code == 0) return 0;
  std::uint8_t reg = 0x01;  // generic error
  switch (code & 0xF000U) {
    case 0x2000:
      reg |= 0x02;  // current
      break;
    case 0x3000:
      reg |= 0x04;  // voltage
      break;
    case 0x4000:
      reg |= 0x08;  // temperature
      break;
    case 0x8000:
      reg |= 0x10;  // communication
      break;
    default:
      break;
  }
  return reg;
}

std::int32_t saturate_i32(double v) {
  if (std::isnan(v)) return 0;
  if (v >= 2147483647.0) return 2147483647;
  if (v <= -2147483648.0) return -2147483647 - 1;
  return static_cast<std::int32_t>(std::lround(v));
}

}  // namespace

const char* silence_name(DriveEmulator::Silence s) {
  switch (s) {
    case DriveEmulator::Silence::None:
      return "none";
    case DriveEmulator::Silence::Heartbeat:
      return "heartbeat";
    case DriveEmulator::Silence::Bus:
      return "bus";
  }
  return "none";
}

DriveEmulator::DriveEmulator(hal::CanBus& bus, const Config& cfg)
    : bus_(bus), cfg_(cfg), od_(cfg.node) {
  position_counts_ = double(cfg.initial_position_counts);
  publish();
}

double DriveEmulator::counts_per_rad() const {
  return cfg_.units.counts_per_rev * cfg_.units.gear_ratio / (2.0 * std::numbers::pi);
}

double DriveEmulator::wheel_speed_radps() const {
  return actual_cps_ / counts_per_rad();
}

double DriveEmulator::wheel_position_rad() const {
  return (position_counts_ - double(cfg_.initial_position_counts)) / counts_per_rad();
}

bool DriveEmulator::torque_on() const {
  return state_ == State::OperationEnabled || state_ == State::QuickStopActive ||
         state_ == State::FaultReactionActive;
}

void DriveEmulator::power_cycle() {
  od_.reset_all();
  state_ = State::NotReadyToSwitchOn;
  nmt_ = NmtState::BootUp;
  boot_pending_ = true;
  last_cw_ = 0;
  rpdo_pending_ = false;
  error_code_ = fault_persistent_ ? error_code_ : 0;
  demand_cps_ = actual_cps_;  // no torque: the wheel coasts from where it was
  publish();
}

// ---- the bus side -------------------------------------------------------------------------

void DriveEmulator::send(const CanFrame& f, bool heartbeat) {
  if (silence_ == Silence::Bus || (heartbeat && silence_ == Silence::Heartbeat)) {
    ++counters_.frames_silenced;
    return;
  }
  if (bus_.send(f)) {
    ++counters_.frames_sent;
  } else {
    ++counters_.frames_refused;
  }
}

void DriveEmulator::send_emcy(std::uint16_t code) {
  if (nmt_ == NmtState::Stopped || nmt_ == NmtState::BootUp) return;  // CiA 301: no EMCY then
  CanFrame f;
  f.id = canopen::kEmcyBase + cfg_.node;
  f.len = 8;
  canopen::put_u16(f.data, code);
  f.data[2] = static_cast<std::uint8_t>(od_.get(0x1001, 0));
  send(f);
  ++counters_.emcys_sent;
}

void DriveEmulator::step(hal::TimeNs now, double dt_s) {
  now_ = now;
  if (boot_pending_) boot();
  CanFrame f;
  while (bus_.receive(f)) {
    ++counters_.frames_received;
    handle(f);
  }
  // CiA 402 transition 1: after its self-test the drive is ready for commands.
  if (state_ == State::NotReadyToSwitchOn && stuck_in_ != State::NotReadyToSwitchOn) {
    set_state(State::SwitchOnDisabled);
  }
  watch_master();
  if (std::isgreater(dt_s, 0.0)) move(dt_s);
  publish();
  send_heartbeat_if_due();
}

void DriveEmulator::boot() {
  boot_pending_ = false;
  master_heard_ = master_lost_ = false;
  tpdo_syncs_[0] = tpdo_syncs_[1] = 0;
  send(canopen::heartbeat(cfg_.node, NmtState::BootUp), true);
  ++counters_.boot_ups_sent;
  set_nmt(NmtState::PreOperational);
  next_heartbeat_ = now_ + hal::TimeNs(od_.get(0x1017, 0)) * 1'000'000;
}

void DriveEmulator::set_nmt(NmtState s) {
  if (s == nmt_) return;
  if (nmt_ == NmtState::Operational) leave_operational();
  nmt_ = s;
  ++counters_.nmt_transitions;
}

void DriveEmulator::leave_operational() {
  // Without PDOs the master can no longer steer the drive: a moving drive stops on its quick
  // stop (CiA 402 abort connection option 0x6007 = 3, fixed here).
  rpdo_pending_ = false;
  if (state_ == State::OperationEnabled) set_state(State::QuickStopActive);
}

void DriveEmulator::handle(const CanFrame& f) {
  if (f.error || f.extended || f.rtr) {
    ++counters_.frames_unknown;
    return;
  }
  const std::uint32_t node = cfg_.node;
  const std::uint32_t rpdo_cob = od_.get(0x1400, 1) & hal::kCanStdIdMask;
  const std::uint32_t hb = od_.get(0x1016, 1);
  const std::uint32_t master = (hb >> 16) & 0xFFU;
  if (f.id == canopen::kNmtId) {
    if (f.len != 2) {
      ++counters_.frames_malformed;
    } else if (f.data[1] != 0 && f.data[1] != node) {
      ++counters_.frames_unknown;
    } else {
      handle_nmt(f);
    }
  } else if (f.id == canopen::kSyncId) {
    if (f.len > 1) {  // CiA 301: 0 bytes, or 1 with the SYNC counter
      ++counters_.frames_malformed;
    } else if (nmt_ != NmtState::Operational) {
      ++counters_.frames_ignored_in_state;
    } else {
      ++counters_.frames_handled;
      handle_sync();
    }
  } else if (f.id == rpdo_cob && pdo_valid(0x1400)) {
    if (nmt_ != NmtState::Operational) {
      ++counters_.frames_ignored_in_state;
    } else if (f.len != 6) {
      ++counters_.frames_malformed;
      send_emcy(kEmcyPdoLength);
    } else {
      ++counters_.frames_handled;
      rpdo_pending_ = true;
      rpdo_cw_ = canopen::get_u16(f.data);
      rpdo_target_ = static_cast<std::int32_t>(canopen::get_u32(f.data + 2));
    }
  } else if (f.id == hal::kSdoRequestBase + node) {
    if (f.len != 8) {
      ++counters_.frames_malformed;
    } else if (nmt_ != NmtState::PreOperational && nmt_ != NmtState::Operational) {
      ++counters_.frames_ignored_in_state;
    } else {
      ++counters_.frames_handled;
      ++counters_.sdo_requests;
      CanFrame resp;
      const std::uint64_t aborts = sdo_.aborts_sent();
      if (sdo_.serve(f, od_, *this, resp)) send(resp);
      counters_.sdo_aborts_sent += sdo_.aborts_sent() - aborts;
    }
  } else if (master != 0 && f.id == canopen::kHeartbeatBase + master) {
    if (f.len != 1) {
      ++counters_.frames_malformed;
    } else {
      ++counters_.frames_handled;
      master_heard_ = true;
      master_lost_ = false;  // heard again: the consumer watches anew
      master_last_ = now_;
    }
  } else {
    ++counters_.frames_unknown;
  }
}

void DriveEmulator::handle_nmt(const CanFrame& f) {
  ++counters_.frames_handled;
  switch (static_cast<canopen::NmtCommand>(f.data[0])) {
    case canopen::NmtCommand::Start:
      set_nmt(NmtState::Operational);
      break;
    case canopen::NmtCommand::Stop:
      set_nmt(NmtState::Stopped);
      break;
    case canopen::NmtCommand::EnterPreOperational:
      set_nmt(NmtState::PreOperational);
      break;
    case canopen::NmtCommand::ResetNode:
      set_nmt(NmtState::BootUp);
      power_cycle();
      boot();
      break;
    case canopen::NmtCommand::ResetCommunication:
      set_nmt(NmtState::BootUp);
      od_.reset_communication();
      boot();
      break;
    default:
      --counters_.frames_handled;
      ++counters_.frames_malformed;  // an NMT command CiA 301 does not define
      break;
  }
}

bool DriveEmulator::pdo_valid(std::uint16_t comm_index) const {
  return (od_.get(comm_index, 1) & 0x80000000U) == 0;
}

void DriveEmulator::handle_sync() {
  ++counters_.syncs;
  if (rpdo_pending_) {
    // Applied at the SYNC (synchronous RPDO): the target first, so an enable sees it.
    rpdo_pending_ = false;
    ++counters_.rpdos_applied;
    od_.set(0x60FF, 0, static_cast<std::uint32_t>(rpdo_target_));
    apply_controlword(rpdo_cw_);
  }
  publish();
  send_tpdos();
}

void DriveEmulator::send_tpdos() {
  const std::uint16_t comm[2] = {0x1800, 0x1801};
  const std::uint16_t map[2] = {0x1A00, 0x1A01};
  const std::uint8_t lens[2] = {6, 4};
  const std::uint32_t mapped[2] = {2, 1};
  const bool corrupt = corrupt_left_ > 0;
  for (int i = 0; i < 2; ++i) {
    // Transmission type n (1 to 240): every n-th SYNC. Mapping checked at download.
    const std::uint32_t every = od_.get(comm[i], 2);
    if (!pdo_valid(comm[i]) || od_.get(map[i], 0) != mapped[i] || every == 0) continue;
    if (++tpdo_syncs_[i] < every) continue;
    tpdo_syncs_[i] = 0;
    CanFrame f;
    f.id = od_.get(comm[i], 1) & hal::kCanStdIdMask;
    f.len = lens[i];
    if (i == 0) {
      canopen::put_u16(f.data, static_cast<std::uint16_t>(od_.get(0x6041, 0)));
      canopen::put_u32(f.data + 2, od_.get(0x606C, 0));
    } else {
      canopen::put_u32(f.data, od_.get(0x6064, 0));
    }
    if (corrupt) {
      --f.len;  // one byte short: a frame the master must refuse and count
      ++counters_.frames_injected;
    } else {
      ++counters_.tpdos_sent;
    }
    send(f);
  }
  if (corrupt) --corrupt_left_;
  if (unknown_left_ > 0) {
    --unknown_left_;
    CanFrame u;
    u.id = 0x380U + cfg_.node;  // TPDO3: nobody configured it
    u.len = 8;
    for (std::uint8_t& b : u.data) b = 0xA5;
    ++counters_.frames_injected;
    send(u);
  }
}

// ---- the SDO server's checks ----------------------------------------------------------------

std::uint32_t DriveEmulator::check_download(const OdEntry& e, std::uint32_t v) {
  const std::uint32_t node = cfg_.node;
  switch (e.index) {
    case 0x1400:
    case 0x1800:
    case 0x1801: {
      if (e.subindex == 1) {
        // Only the predefined COB-ID (bit 31: PDO not valid; bit 30: no RTR) is accepted.
        const std::uint32_t base =
            e.index == 0x1400 ? canopen::kRpdo1Base
                              : (e.index == 0x1800 ? canopen::kTpdo1Base : canopen::kTpdo2Base);
        return (v & 0x3FFFFFFFU) == base + node ? 0 : kAbortValueRange;
      }
      // Transmission type: RPDO 0-240 (all applied at the next SYNC), TPDO 1-240 (every n-th).
      const std::uint32_t lowest = e.index == 0x1400 ? 0 : 1;
      return v >= lowest && v <= 240 ? 0 : kAbortValueRange;
    }
    case 0x1600:
    case 0x1A00:
    case 0x1A01: {
      // Fixed mapping (docs/can-protocol.md): the master may write it again, not change it.
      const std::uint16_t comm = e.index == 0x1600 ? 0x1400 : (e.index == 0x1A00 ? 0x1800 : 0x1801);
      if (pdo_valid(comm)) return kAbortDeviceState;  // CiA 301: map only an invalid PDO
      const std::uint32_t count = e.index == 0x1A01 ? 1 : 2;
      if (e.subindex == 0) {
        if (v == 0) return 0;
        if (v > count) return kAbortMappingTooLong;
        if (v < count) return kAbortCannotMap;
        for (std::uint8_t s = 1; s <= count; ++s) {
          if (od_.get(e.index, s) != od_.default_value(e.index, s)) return kAbortCannotMap;
        }
        return 0;
      }
      if (od_.get(e.index, 0) != 0) return kAbortDeviceState;  // CiA 301: sub 0 = 0 first
      return v == od_.default_value(e.index, e.subindex) ? 0 : kAbortCannotMap;
    }
    case 0x1016:
      return ((v >> 16) & 0xFFU) <= canopen::kMaxNodeId && (v >> 24) == 0 ? 0 : kAbortValueRange;
    case 0x605A: {
      const auto code = static_cast<std::int16_t>(v);
      // 0 coast, 1/2 slow down or quick stop ramp then disabled, 5/6 the same and stay.
      return code == 0 || code == 1 || code == 2 || code == 5 || code == 6 ? 0 : kAbortValueRange;
    }
    case 0x6060: {
      const auto mode = static_cast<std::int8_t>(v);
      return mode == 0 || mode == canopen::kProfileVelocityMode ? 0 : kAbortValueRange;
    }
    case 0x6083:
    case 0x6084:
    case 0x6085:
      return v == 0 ? kAbortValueTooLow : 0;
    default:
      return 0;
  }
}

void DriveEmulator::after_download(const OdEntry& e) {
  switch (e.index) {
    case 0x1017:  // the producer restarts on the new period
      next_heartbeat_ = now_ + hal::TimeNs(e.value) * 1'000'000;
      break;
    case 0x1016:  // a new consumer: armed by the master's next heartbeat
      master_heard_ = master_lost_ = false;
      break;
    case 0x6040:
      apply_controlword(static_cast<std::uint16_t>(e.value));
      break;
    case 0x6060:
      od_.set(0x6061, 0, e.value);
      break;
    default:
      break;
  }
  publish();
}

// ---- CiA 402 --------------------------------------------------------------------------------

void DriveEmulator::set_state(State s) {
  if (s == state_) return;
  const bool had_torque = torque_on();
  state_ = s;
  ++counters_.state_transitions;
  if (!had_torque && torque_on()) demand_cps_ = actual_cps_;  // take over a coasting wheel
  publish();
}

void DriveEmulator::apply_controlword(std::uint16_t cw) {
  const bool reset_edge = (cw & 0x80U) != 0 && (last_cw_ & 0x80U) == 0;
  last_cw_ = cw;
  od_.set(0x6040, 0, cw);
  if (state_ == State::Fault) {
    if (reset_edge && !fault_persistent_) {
      error_code_ = 0;
      od_.set(0x1001, 0, 0);
      od_.set(0x603F, 0, 0);
      ++counters_.fault_resets;
      send_emcy(kEmcyErrorReset);
      set_state(State::SwitchOnDisabled);
    }
    return;
  }
  if (state_ == State::FaultReactionActive || state_ == State::NotReadyToSwitchOn) return;
  const Command c = decode_command(cw);
  State next = state_;
  switch (c) {
    case Command::DisableVoltage:
      next = State::SwitchOnDisabled;
      break;
    case Command::QuickStop:
      next = state_ == State::OperationEnabled  ? State::QuickStopActive
             : state_ == State::QuickStopActive ? state_
                                                : State::SwitchOnDisabled;
      break;
    case Command::Shutdown:
      if (state_ != State::QuickStopActive) next = State::ReadyToSwitchOn;
      break;
    case Command::SwitchOn:  // from Operation enabled: disable operation
      if (state_ == State::ReadyToSwitchOn || state_ == State::OperationEnabled) {
        next = State::SwitchedOn;
      }
      break;
    case Command::Enable: {
      const auto option = static_cast<std::int16_t>(od_.get(0x605A, 0));
      if (state_ == State::ReadyToSwitchOn) next = State::SwitchedOn;
      if (state_ == State::SwitchedOn) next = State::OperationEnabled;
      if (state_ == State::QuickStopActive && option >= 5) next = State::OperationEnabled;
      break;
    }
    case Command::None:
      break;
  }
  // A drive told to refuse does not leave its state toward Operation enabled.
  const bool forward = (state_ == State::SwitchOnDisabled && next == State::ReadyToSwitchOn) ||
                       (state_ == State::ReadyToSwitchOn && next == State::SwitchedOn) ||
                       (state_ == State::SwitchedOn && next == State::OperationEnabled);
  if (forward && state_ == stuck_in_) {
    ++counters_.transitions_refused;
    return;
  }
  set_state(next);
}

void DriveEmulator::enter_fault(std::uint16_t code) {
  if ((state_ == State::Fault || state_ == State::FaultReactionActive) && code == error_code_) {
    return;
  }
  error_code_ = code;
  od_.set(0x603F, 0, code);
  od_.set(0x1001, 0, error_register(code));
  ++counters_.faults;
  send_emcy(code);
  // Fault reaction: a drive with torque brakes on the quick stop ramp, one without has nothing
  // to stop and is in Fault at once.
  const bool braking = torque_on();
  if (state_ != State::Fault) set_state(braking ? State::FaultReactionActive : State::Fault);
}

void DriveEmulator::inject_fault(std::uint16_t error_code, bool persistent) {
  fault_persistent_ = persistent;
  enter_fault(error_code);
}

void DriveEmulator::watch_master() {
  const std::uint32_t hb = od_.get(0x1016, 1);
  const hal::TimeNs timeout = hal::TimeNs(hb & 0xFFFFU) * 1'000'000;
  // CiA 301: the consumer watches from the first heartbeat heard; time 0 or node 0: off.
  if (!master_heard_ || master_lost_ || timeout == 0 || ((hb >> 16) & 0xFFU) == 0) return;
  if (now_ - master_last_ <= timeout) return;
  master_lost_ = true;
  ++counters_.master_heartbeat_losses;
  // The master is gone: nobody steers this wheel any more, so it stops by itself (the fault
  // reaction ramps it down), and NMT falls back to Pre-operational (0x1029 default).
  enter_fault(kEmcyHeartbeatLost);
  if (nmt_ == NmtState::Operational) set_nmt(NmtState::PreOperational);
}

void DriveEmulator::move(double dt) {
  const auto option = static_cast<std::int16_t>(od_.get(0x605A, 0));
  const double accel = double(od_.get(0x6083, 0)) * dt;
  const double decel = double(od_.get(0x6084, 0)) * dt;
  const double quick = double(od_.get(0x6085, 0)) * dt;
  if (state_ == State::QuickStopActive && option == 0) {
    set_state(State::SwitchOnDisabled);  // option 0: the drive function is disabled at once
  }
  if (torque_on()) {
    if (state_ == State::OperationEnabled) {
      const std::uint16_t cw = static_cast<std::uint16_t>(od_.get(0x6040, 0));
      const bool pv = static_cast<std::int8_t>(od_.get(0x6061, 0)) == canopen::kProfileVelocityMode;
      // Halt (bit 8) or no profile velocity mode selected: hold still on the deceleration ramp.
      const bool halted = (cw & hal::cia402::kCwHalt) != 0 || !pv;
      const double target = halted ? 0.0 : double(static_cast<std::int32_t>(od_.get(0x60FF, 0)));
      demand_cps_ = ramp(demand_cps_, target, accel, decel);
    } else {
      const bool slow = state_ == State::QuickStopActive && (option == 1 || option == 5);
      demand_cps_ = ramp(demand_cps_, 0.0, accel, slow ? decel : quick);
    }
    const double alpha =
        std::isgreater(cfg_.velocity_tau_s, 0.0) ? 1.0 - std::exp(-dt / cfg_.velocity_tau_s) : 1.0;
    actual_cps_ += (demand_cps_ - actual_cps_) * alpha;
  } else {
    const double alpha =
        std::isgreater(cfg_.coast_tau_s, 0.0) ? 1.0 - std::exp(-dt / cfg_.coast_tau_s) : 1.0;
    actual_cps_ -= actual_cps_ * alpha;
    demand_cps_ = 0.0;
  }
  if (demand_cps_ == 0.0 && std::fabs(actual_cps_) < kStoppedCps) actual_cps_ = 0.0;
  position_counts_ += actual_cps_ * dt;
  const bool stopped = demand_cps_ == 0.0 && actual_cps_ == 0.0;
  if (stopped && state_ == State::FaultReactionActive) set_state(State::Fault);
  if (stopped && state_ == State::QuickStopActive && (option == 1 || option == 2)) {
    set_state(State::SwitchOnDisabled);
  }
}

std::uint16_t DriveEmulator::statusword() const {
  std::uint16_t sw = 0;
  switch (state_) {
    case State::NotReadyToSwitchOn:
    case State::Unknown:
      break;
    case State::SwitchOnDisabled:
      sw = 0x0040;
      break;
    case State::ReadyToSwitchOn:
      sw = 0x0021;
      break;
    case State::SwitchedOn:
      sw = 0x0023;
      break;
    case State::OperationEnabled:
      sw = 0x0027;
      break;
    case State::QuickStopActive:
      sw = 0x0007;
      break;
    case State::FaultReactionActive:
      sw = 0x000F;
      break;
    case State::Fault:
      sw = 0x0008;
      break;
  }
  if (state_ != State::NotReadyToSwitchOn && state_ != State::SwitchOnDisabled &&
      state_ != State::Fault) {
    sw |= hal::cia402::kSwVoltageEnabled;
  }
  sw |= hal::cia402::kSwRemote;  // the drive follows the bus
  const double window = cfg_.target_window_radps * counts_per_rad();
  if (state_ == State::OperationEnabled) {
    const std::uint16_t cw = static_cast<std::uint16_t>(od_.get(0x6040, 0));
    const bool halted = (cw & hal::cia402::kCwHalt) != 0;
    const double target = halted ? 0.0 : double(static_cast<std::int32_t>(od_.get(0x60FF, 0)));
    if (std::fabs(actual_cps_ - target) <= window) sw |= hal::cia402::kSwTargetReached;
  } else if (state_ == State::QuickStopActive && actual_cps_ == 0.0) {
    sw |= hal::cia402::kSwTargetReached;  // at rest after the quick stop
  }
  if (std::fabs(actual_cps_) <= window) sw |= 1U << 12;  // pv mode: speed is zero
  return sw;
}

void DriveEmulator::publish() {
  od_.set(0x6041, 0, statusword());
  od_.set(0x606B, 0, static_cast<std::uint32_t>(saturate_i32(demand_cps_)));
  od_.set(0x606C, 0, static_cast<std::uint32_t>(saturate_i32(actual_cps_)));
  // Position actual is a 32-bit counter: the low 32 bits of the whole count, wrapping.
  const auto whole = static_cast<std::int64_t>(std::llround(position_counts_));
  od_.set(0x6064, 0, static_cast<std::uint32_t>(static_cast<std::uint64_t>(whole)));
}

void DriveEmulator::send_heartbeat_if_due() {
  const hal::TimeNs period = hal::TimeNs(od_.get(0x1017, 0)) * 1'000'000;
  if (period == 0 || nmt_ == NmtState::BootUp || now_ < next_heartbeat_) return;
  send(canopen::heartbeat(cfg_.node, nmt_), true);
  ++counters_.heartbeats_sent;
  next_heartbeat_ += period;
  if (next_heartbeat_ <= now_) next_heartbeat_ = now_ + period;  // a late step: no burst
}

}  // namespace carril::sim
