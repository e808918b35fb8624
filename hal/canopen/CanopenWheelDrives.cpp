// The cyclic part of the CANopen master: sync(), frame dispatch, fault latches, bus-off. The
// bring-up and config checks are in CanopenBringUp.cpp.
#include "hal/canopen/CanopenWheelDrives.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "hal/canopen/Frames.hpp"

namespace carril::hal::canopen {

using cia402::Goal;
using cia402::State;

namespace {
bool faulted(State s) {
  return s == State::Fault || s == State::FaultReactionActive;
}

long long ms(TimeNs t) {
  return static_cast<long long>(t / 1'000'000);
}
}  // namespace

const char* CanopenWheelDrives::label(int i, char* buf, std::size_t n) const {
  const char* name = cfg_.name[i];
  if (name != nullptr && name[0] != '\0') {
    std::snprintf(buf, n, "drive %d (%s, node %u)", i, name, unsigned(cfg_.drive[i].node));
  } else {
    std::snprintf(buf, n, "drive %d (node %u)", i, unsigned(cfg_.drive[i].node));
  }
  return buf;
}

void CanopenWheelDrives::enable() {
  goal_ = Goal::Enabled;
  for (int i = 0; i < cfg_.wheels; ++i) drive_[i].enable_since_ns = -1;
}

void CanopenWheelDrives::disable() {
  goal_ = Goal::Disabled;
}

void CanopenWheelDrives::quick_stop() {
  goal_ = Goal::QuickStop;
}

void CanopenWheelDrives::reset_faults() {
  const TimeNs now = clock_.now_ns();
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    if (d.latch != 0) {
      // A latch clears only once its cause is gone: the drive was heard since (after a lost
      // heartbeat or a bus-off) or at least is not silent (after an EMCY or a stuck enable).
      const HeartbeatMonitor::Node* hb = heartbeats_.find(cfg_.drive[i].node);
      const bool alive = hb != nullptr && hb->heard && !hb->lost && !bus_down_;
      const bool heard_since = alive && hb->last_ns > d.latch_ns;
      const bool communication = d.latch == kFaultHeartbeatLost || d.latch == kFaultBusDown;
      if (d.latch == kFaultRebooted || !alive || (communication && !heard_since)) continue;
      // Feedback clears once a whole SYNC period brought good feedback again.
      if (d.latch == kFaultFeedback && d.bad_periods != 0) continue;
      if (d.latch == kFaultNotOperational &&
          hb->state != static_cast<std::uint8_t>(NmtState::Operational)) {
        // Ask it back; the latch clears at a later reset_faults() once its heartbeat agrees.
        send(nmt(NmtCommand::Start, cfg_.drive[i].node), now);
        continue;
      }
      d.latch = 0;
      d.latch_generic = false;
    }
    if (d.sw_heard && faulted(cia402::decode_statusword(d.statusword))) {
      d.reset_request = true;  // exactly one reset per call: PowerStateMachine sends one edge
      d.reset_since_ns = now;
    }
  }
}

void CanopenWheelDrives::set_velocity(const float* radps, int n) {
  for (int i = 0; i < n && i < cfg_.wheels; ++i) drive_[i].target_radps = radps[i];
}

void CanopenWheelDrives::sync() {
  // The period's frames leave together: one system call on a batching transport.
  const FlushOnExit flush{bus_};
  if (phase_ != Phase::Ready) return;  // nothing brought up: nothing to drive
  const TimeNs now = clock_.now_ns();
  receive(now);
  watch_heartbeats(now);
  if (bus_down_) {
    probe(now);
    if (bus_down_) return;
  }
  if (!exchange_pdos(now)) return;
  master_heartbeat(now);
}

void CanopenWheelDrives::read(WheelFeedbackSet& out) const {
  out.count = static_cast<std::uint8_t>(cfg_.wheels);
  for (int i = 0; i < cfg_.wheels; ++i) {
    const Drive& d = drive_[i];
    const cia402::DriveUnits& u = cfg_.drive[i].units;
    WheelFeedback& w = out.wheel[i];
    w.stamp_ns = d.stamp_ns;
    const double sign = cfg_.drive[i].inverted ? -1.0 : 1.0;
    w.velocity_radps = static_cast<float>(sign * cia402::to_wheel_radps(d.velocity_counts, u));
    w.position_rad = sign * d.position.wheel_rad(u);
    w.fault = DriveFault::None;
    const State s = d.sw_heard ? cia402::decode_statusword(d.statusword) : State::Unknown;
    // A raw CiA 301 / 402 code: the firmware compares it with None and logs the number.
    if (d.latch != 0) {
      w.state = DriveState::Fault;
      w.fault = static_cast<DriveFault>(d.latch);
    } else if (faulted(s)) {
      w.state = DriveState::Fault;
      w.fault = static_cast<DriveFault>(d.emcy_code != 0 ? d.emcy_code : kFaultGeneric);
    } else if (phase_ != Phase::Ready) {
      w.state = DriveState::Disabled;
    } else if (s == State::QuickStopActive || goal_ == Goal::QuickStop) {
      w.state = DriveState::QuickStop;
    } else if (s == State::OperationEnabled) {
      w.state = DriveState::Enabled;
    } else {
      w.state = goal_ == Goal::Enabled ? DriveState::Enabling : DriveState::Disabled;
    }
  }
}

void CanopenWheelDrives::receive(TimeNs now) {
  CanFrame f;
  for (int k = 0; k < cfg_.max_reads; ++k) {  // bounded: the rest waits for the next tick
    if (!bus_.receive(f)) break;
    dispatch(f, now);
  }
}

int CanopenWheelDrives::drive_of(std::uint8_t node) const {
  for (int i = 0; i < cfg_.wheels; ++i) {
    if (cfg_.drive[i].node == node) return i;
  }
  return -1;
}

void CanopenWheelDrives::dispatch(const CanFrame& f, TimeNs now) {
  ++counters_.frames_read;
  if (f.error) {
    ++counters_.error_frames;
    if ((f.id & kCanErrBusOff) != 0) bus_down(now, "bus-off (error frame)");
    return;
  }
  const std::uint32_t function = f.id & 0x780U;
  const auto node = static_cast<std::uint8_t>(f.id & 0x7FU);
  const bool consumed = function == kEmcyBase || function == kTpdo1Base || function == kTpdo2Base ||
                        function == kSdoResponseBase || function == kHeartbeatBase;
  if (f.extended || !consumed || node == 0) {
    ++counters_.unknown_cob;
    return;
  }
  const int i = drive_of(node);
  if (i < 0) {
    ++counters_.unknown_node;
    return;
  }
  if (f.rtr) {
    ++counters_.malformed;
    return;
  }
  Drive& d = drive_[i];
  switch (function) {
    case kHeartbeatBase: {
      if (!heartbeats_.on_frame(f, now)) {
        ++counters_.malformed;
        return;
      }
      ++counters_.heartbeats;
      if (phase_ != Phase::Ready) return;
      const std::uint8_t state = f.data[0] & 0x7FU;
      if (state == static_cast<std::uint8_t>(NmtState::BootUp)) {
        latch(i, kFaultRebooted, now, "boot-up while running: its setup is lost, run init()");
      } else if (state != static_cast<std::uint8_t>(NmtState::Operational)) {
        // Its PDOs stopped: the statusword and speeds the master holds are stale.
        latch(i, kFaultNotOperational, now, "left Operational: heartbeat says %s",
              nmt_state_name(state));
      }
      return;
    }
    case kEmcyBase: {
      Emcy e;
      if (!decode_emcy(f, e)) {
        ++counters_.malformed;
        return;
      }
      ++counters_.emcy;
      ++d.emcy_count;
      if (e.error_code == 0) return;  // "error reset or no error": nothing to latch
      d.emcy_code = e.error_code;
      latch(i, e.error_code, now, "EMCY 0x%04X %s (error register 0x%02X)", unsigned(e.error_code),
            emcy_meaning(e.error_code), unsigned(e.error_register));
      return;
    }
    case kTpdo1Base: {
      std::uint16_t statusword = 0;
      std::int32_t velocity = 0;
      if (!decode_tpdo1(f, node, statusword, velocity)) {
        ++counters_.malformed;
        d.bad_why = "TPDO1 malformed";
        return;
      }
      ++counters_.tpdo1;
      // A speed no wheel of this robot can reach is a corrupt frame: its statusword is not
      // trusted either, and the period counts as bad.
      const double limit = cfg_.drive[i].max_wheel_radps * 1.5;
      if (std::abs(cia402::to_wheel_radps(velocity, cfg_.drive[i].units)) > limit) {
        ++counters_.implausible;
        d.bad_why = "velocity actual beyond 1.5 times max_wheel_radps";
        return;
      }
      d.statusword = statusword;
      d.velocity_counts = velocity;
      d.sw_heard = true;
      d.tpdo1_fresh = true;
      d.stamp_ns = last_sync_ns_;  // sampled at the SYNC it answers
      return;
    }
    case kTpdo2Base: {
      std::int32_t position = 0;
      if (!decode_tpdo2(f, node, position)) {
        ++counters_.malformed;
        d.bad_why = "TPDO2 malformed";
        return;
      }
      ++counters_.tpdo2;
      if (!plausible_position(d, i, position)) {
        // The odometry does not take the jump: it resumes from the new reading.
        ++counters_.implausible;
        d.bad_why = "position actual jumped further than max_wheel_radps allows";
        d.position.rebase(position);
      } else {
        d.position.add(position);
        d.tpdo2_fresh = true;
      }
      d.position_heard = true;
      d.raw_position = position;
      d.raw_position_sync_ns = last_sync_ns_;
      return;
    }
    default: {  // kSdoResponseBase
      if (f.len != 8) {
        ++counters_.malformed;
        return;
      }
      ++counters_.sdo_responses;
      d.sdo->on_frame(f);
      return;
    }
  }
}

void CanopenWheelDrives::watch_heartbeats(TimeNs now) {
  heartbeats_.poll(now);
  for (int i = 0; i < cfg_.wheels; ++i) {
    const HeartbeatMonitor::Node* hb = heartbeats_.find(cfg_.drive[i].node);
    if (hb == nullptr || hb->losses == drive_[i].losses_seen) continue;
    drive_[i].losses_seen = hb->losses;
    ++counters_.heartbeat_losses;
    latch(i, kFaultHeartbeatLost, now, "heartbeat lost: silent for %lld ms (consumer time %lld ms)",
          ms(now - hb->last_ns), ms(cfg_.heartbeat_consumer_ns));
  }
}

bool CanopenWheelDrives::any_latch() const {
  for (int i = 0; i < cfg_.wheels; ++i) {
    if (drive_[i].latch != 0) return true;
  }
  return false;
}

Goal CanopenWheelDrives::goal_of(int) const {
  // One latched fault stops every wheel: a robot on one driven wheel turns on the spot.
  return any_latch() ? Goal::QuickStop : goal_;
}

void CanopenWheelDrives::check_faults(TimeNs now) {
  char since[32];  // "%lld.%03lld s" of any long long fits (GCC checks it at -O0)
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    const State s = d.sw_heard ? cia402::decode_statusword(d.statusword) : State::Unknown;
    if (d.reset_since_ns >= 0) {
      // A reset was asked for: the drive has enable_timeout_ns to leave Fault.
      if (d.sw_heard && !faulted(s) && !d.reset_request) {
        d.reset_since_ns = -1;
      } else if (now - d.reset_since_ns > cfg_.enable_timeout_ns) {
        d.reset_since_ns = -1;
        d.reset_request = false;
        latch(i, d.emcy_code != 0 ? d.emcy_code : kFaultGeneric, now,
              "fault reset did not clear the Fault within %lld ms", ms(cfg_.enable_timeout_ns));
      }
    } else if (faulted(s) && d.latch == 0) {
      latch(i, kFaultGeneric, now, "in %s (statusword 0x%04X), no EMCY", cia402::state_name(s),
            unsigned(d.statusword));
    }
    if (goal_of(i) == Goal::Enabled && !d.psm.at_goal()) {
      if (d.enable_since_ns < 0) {
        d.enable_since_ns = now;
      } else if (now - d.enable_since_ns > cfg_.enable_timeout_ns) {
        const long long t = ms(now - d.enable_since_ns);
        std::snprintf(since, sizeof since, "%lld.%03lld s", t / 1000, t % 1000);
        latch(i, kFaultEnableTimeout, now, "stuck in %s, waiting for %s after %s",
              cia402::state_name(d.psm.state()), cia402::state_name(d.psm.awaiting()), since);
      }
    } else {
      d.enable_since_ns = -1;
    }
  }
}

bool CanopenWheelDrives::plausible_position(Drive& d, int i, std::int32_t counts) const {
  if (!d.position_heard) return true;
  const auto step = static_cast<std::int32_t>(static_cast<std::uint32_t>(counts) -
                                              static_cast<std::uint32_t>(d.raw_position));
  // Since the SYNC of the last reading, plus one period of jitter in when a SYNC goes out.
  const TimeNs dt =
      std::max<TimeNs>(last_sync_ns_ - d.raw_position_sync_ns, 0) + cfg_.control_period_ns;
  const double limit_counts = cfg_.drive[i].max_wheel_radps * 1.5 * cfg_.drive[i].units.gear_ratio *
                                  cfg_.drive[i].units.counts_per_rev / (2.0 * std::numbers::pi) *
                                  double(dt) * 1e-9 +
                              2.0;
  return std::abs(double(step)) <= limit_counts;
}

void CanopenWheelDrives::supervise_feedback(TimeNs now) {
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    const bool bad = d.bad_why != nullptr || !d.tpdo1_fresh || !d.tpdo2_fresh;
    if (!bad) {
      d.bad_periods = 0;
    } else {
      ++counters_.feedback_bad;
      ++d.bad_periods;
      d.last_bad = d.bad_why != nullptr               ? d.bad_why
                   : !d.tpdo1_fresh && !d.tpdo2_fresh ? "no TPDO1 nor TPDO2"
                   : !d.tpdo1_fresh                   ? "no TPDO1 (statusword, velocity)"
                                                      : "no TPDO2 (position)";
      if (d.bad_periods >= cfg_.feedback_missed_syncs) {
        latch(i, kFaultFeedback, now, "feedback bad for %d SYNC periods in a row (last: %s)",
              d.bad_periods, d.last_bad);
      }
    }
  }
}

bool CanopenWheelDrives::exchange_pdos(TimeNs now) {
  // The feedback due since the last SYNC: judged only once a SYNC went out while running.
  if (sync_outstanding_) supervise_feedback(now);
  for (int i = 0; i < cfg_.wheels; ++i) {
    drive_[i].tpdo1_fresh = drive_[i].tpdo2_fresh = false;
    drive_[i].bad_why = nullptr;
  }
  // Faults first, so a fault found on any drive stops every drive in this same period.
  check_faults(now);
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    const Goal goal = goal_of(i);
    const std::uint32_t resets = d.psm.fault_resets();
    // Before the first TPDO the drive is taken as Not ready to switch on: controlword 0.
    const std::uint16_t cw = d.psm.step(d.statusword, goal, d.reset_request);
    if (d.psm.fault_resets() != resets) {
      d.reset_request = false;  // sent: no second attempt until the next reset_faults()
      ++counters_.fault_resets;
    } else if (d.sw_heard && !faulted(d.psm.state())) {
      d.reset_request = false;  // left Fault by itself
    }
    const bool run = goal == Goal::Enabled && d.psm.state() == State::OperationEnabled;
    const std::int32_t target =
        run ? cia402::to_counts_per_s(
                  cfg_.drive[i].inverted ? -double(d.target_radps) : double(d.target_radps),
                  cfg_.drive[i].units)
            : 0;
    if (!send(rpdo1(cfg_.drive[i].node, cw, target), now)) return false;
  }
  if (!send(sync_frame(), now)) return false;
  ++counters_.syncs;
  last_sync_ns_ = now;
  sync_outstanding_ = phase_ == Phase::Ready;
  return true;
}

void CanopenWheelDrives::master_heartbeat(TimeNs now) {
  if (now < next_master_hb_ns_) return;
  next_master_hb_ns_ = std::max(next_master_hb_ns_ + cfg_.master_heartbeat_ns, now);
  send(heartbeat(cfg_.master_node, NmtState::Operational), now);
}

bool CanopenWheelDrives::send(const CanFrame& f, TimeNs now) {
  if (bus_.send(f)) return true;
  ++counters_.send_refused;
  bus_down(now, "send refused (interface down or transmit queue full)");
  return false;
}

void CanopenWheelDrives::bus_down(TimeNs now, const char* why) {
  if (bus_down_) return;
  bus_down_ = true;
  sync_outstanding_ = false;  // no SYNC reaches the drives: nothing is due
  ++counters_.bus_offs;
  ++counters_.faults;
  backoff_ns_ = cfg_.backoff_min_ns;
  next_probe_ns_ = now + backoff_ns_;
  goal_ = Goal::QuickStop;
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    d.latch = kFaultBusDown;  // overrides any other cause: nothing reaches the drives now
    d.latch_ns = now;
    d.latch_generic = false;
    d.reset_request = false;
    d.reset_since_ns = -1;
  }
  std::snprintf(last_fault_, kMaxText,
                "CAN %s: every drive taken as faulted, probing every %lld ms", why,
                ms(backoff_ns_));
  keep_first_fault();
}

void CanopenWheelDrives::keep_first_fault() {
  if (first_fault_[0] == '\0') std::memcpy(first_fault_, last_fault_, sizeof first_fault_);
}

void CanopenWheelDrives::probe(TimeNs now) {
  if (now < next_probe_ns_) return;
  ++counters_.probes;
  if (bus_.send(heartbeat(cfg_.master_node, NmtState::Operational))) {
    // The port takes frames again; the drives resume only once heard, reset and re-enabled.
    bus_down_ = false;
    next_master_hb_ns_ = now + cfg_.master_heartbeat_ns;
    return;
  }
  ++counters_.send_refused;
  backoff_ns_ = std::min(backoff_ns_ * 2, cfg_.backoff_max_ns);
  next_probe_ns_ = now + backoff_ns_;
}

void CanopenWheelDrives::latch(int i, std::uint16_t code, TimeNs now, const char* fmt, ...) {
  Drive& d = drive_[i];
  // The first cause stays, except that an EMCY names a fault first seen in the statusword.
  if (d.latch != 0 && !(d.latch_generic && code != kFaultGeneric)) return;
  d.latch = code;
  d.latch_ns = now;
  d.latch_generic = code == kFaultGeneric;
  d.enable_since_ns = -1;
  goal_ = Goal::QuickStop;  // resuming takes reset_faults() and enable()
  ++counters_.faults;
  char who[64];
  const int k = std::snprintf(last_fault_, kMaxText, "%s: ", label(i, who, sizeof who));
  if (k < 0 || k >= kMaxText) return;
  std::va_list args;
  va_start(args, fmt);
  std::vsnprintf(last_fault_ + k, std::size_t(kMaxText - k), fmt, args);
  va_end(args);
  keep_first_fault();
}

}  // namespace carril::hal::canopen
