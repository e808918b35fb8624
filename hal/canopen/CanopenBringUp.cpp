// CanopenWheelDrives: the config check and the bring-up state machine (NMT reset communication,
// boot-up, SDO setup writes, NMT start, operational, enable, disable). The cyclic part is in
// CanopenWheelDrives.cpp.
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "hal/canopen/CanopenWheelDrives.hpp"
#include "hal/canopen/Frames.hpp"
#include "hal/canopen/SdoAbort.hpp"

namespace carril::hal::canopen {

using cia402::Goal;

namespace {
constexpr TimeNs kMsNs = 1'000'000;

// "1.5 s", integer arithmetic only.
const char* seconds(TimeNs t, char* buf, std::size_t n) {
  const long long ms = static_cast<long long>(t / kMsNs);
  if (ms % 100 == 0) {
    std::snprintf(buf, n, "%lld.%lld s", ms / 1000, (ms % 1000) / 100);
  } else {
    std::snprintf(buf, n, "%lld.%03lld s", ms / 1000, ms % 1000);
  }
  return buf;
}

bool positive(double v) {
  return std::isfinite(v) && std::isgreater(v, 0.0);
}
}  // namespace

CanopenWheelDrives::CanopenWheelDrives(CanBus& bus, Clock& clock, BringUpWaiter& waiter,
                                       const CanopenConfig& cfg)
    : bus_(bus), clock_(clock), waiter_(waiter), cfg_(cfg) {
  const char* err = validate();
  if (err != nullptr) {
    // Keep every loop in bounds; init() reports the error.
    if (cfg_.wheels < 0 || cfg_.wheels > kMaxWheels) cfg_.wheels = 0;
    return;
  }
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    d.sdo.emplace(bus_, SdoClient::Config{cfg_.drive[i].node, cfg_.sdo_timeout_ns});
    d.n_writes = setup_writes(cfg_.drive[i], d.writes);
  }
}

const char* CanopenWheelDrives::validate() {
  char* e = config_error_;
  const std::size_t n = sizeof config_error_;
  const CanopenConfig& c = cfg_;
  if (c.wheels < 1 || c.wheels > kMaxWheels) {
    std::snprintf(e, n, "wheels = %d: expected 1 to %d", c.wheels, kMaxWheels);
    return e;
  }
  if (c.master_node < 1 || c.master_node > kMaxNodeId) {
    std::snprintf(e, n, "master_node = %u: expected 1 to 127", unsigned(c.master_node));
    return e;
  }
  struct Time {
    const char* name;
    TimeNs value;
  };
  const Time times[] = {{"master_heartbeat_ns", c.master_heartbeat_ns},
                        {"control_period_ns", c.control_period_ns},
                        {"heartbeat_consumer_ns", c.heartbeat_consumer_ns},
                        {"sdo_timeout_ns", c.sdo_timeout_ns},
                        {"boot_timeout_ns", c.boot_timeout_ns},
                        {"enable_timeout_ns", c.enable_timeout_ns},
                        {"bring_up_poll_ns", c.bring_up_poll_ns},
                        {"backoff_min_ns", c.backoff_min_ns}};
  for (const Time& t : times) {
    if (t.value <= 0) {
      std::snprintf(e, n, "%s = %lld: expected a positive time [ns]", t.name,
                    static_cast<long long>(t.value));
      return e;
    }
  }
  if (c.backoff_max_ns < c.backoff_min_ns) {
    std::snprintf(e, n, "backoff_max_ns = %lld: expected at least backoff_min_ns (%lld)",
                  static_cast<long long>(c.backoff_max_ns),
                  static_cast<long long>(c.backoff_min_ns));
    return e;
  }
  if (c.max_reads < 1 || c.max_reads > 4096) {
    std::snprintf(e, n, "max_reads = %d: expected 1 to 4096 frames per sync", c.max_reads);
    return e;
  }
  if (c.feedback_missed_syncs < 2 || c.feedback_missed_syncs > 1000) {
    std::snprintf(e, n,
                  "feedback_missed_syncs = %d: expected 2 to 1000 SYNC periods (one late frame "
                  "must not stop the robot)",
                  c.feedback_missed_syncs);
    return e;
  }
  for (int i = 0; i < c.wheels; ++i) {
    const DriveSetup& d = c.drive[i];
    if (!positive(d.max_wheel_radps)) {
      std::snprintf(e, n, "drive[%d].max_wheel_radps = %g: expected a positive speed [rad/s]", i,
                    d.max_wheel_radps);
      return e;
    }
    if (d.node < 1 || d.node > kMaxNodeId) {
      std::snprintf(e, n, "drive[%d].node = %u: expected 1 to 127", i, unsigned(d.node));
      return e;
    }
    if (d.node == c.master_node) {
      std::snprintf(e, n, "drive[%d].node = %u: that is master_node, the master's own id", i,
                    unsigned(d.node));
      return e;
    }
    for (int j = 0; j < i; ++j) {
      if (c.drive[j].node == d.node) {
        std::snprintf(e, n, "drive[%d].node = %u: drive[%d] has it too", i, unsigned(d.node), j);
        return e;
      }
    }
    if (!positive(d.units.counts_per_rev) || !positive(d.units.gear_ratio)) {
      std::snprintf(e, n,
                    "drive[%d].units: counts_per_rev = %g, gear_ratio = %g: expected positive "
                    "numbers",
                    i, d.units.counts_per_rev, d.units.gear_ratio);
      return e;
    }
    if (d.master_node != c.master_node) {
      std::snprintf(e, n,
                    "drive[%d].master_node = %u: expected master_node (%u), whose heartbeat "
                    "the drive watches",
                    i, unsigned(d.master_node), unsigned(c.master_node));
      return e;
    }
    if (TimeNs(d.master_timeout_ms) * kMsNs <= c.master_heartbeat_ns) {
      std::snprintf(e, n,
                    "drive[%d].master_timeout_ms = %u: expected more than master_heartbeat_ns "
                    "(%lld ms), or the drive stops while the master is alive",
                    i, unsigned(d.master_timeout_ms),
                    static_cast<long long>(c.master_heartbeat_ns / kMsNs));
      return e;
    }
    // A heartbeat is read up to one control period after it came, and the loss is found at
    // the first sync() after the consumer time: the wheels stop within consumer time + 2
    // control periods of the last heartbeat, which must be at most 3 heartbeat periods.
    const TimeNs period = TimeNs(d.heartbeat_ms) * kMsNs;
    if (period <= 0 || c.heartbeat_consumer_ns <= period ||
        c.heartbeat_consumer_ns + 2 * c.control_period_ns > 3 * period) {
      std::snprintf(e, n,
                    "heartbeat_consumer_ns = %lld ms: expected more than drive[%d].heartbeat_ms "
                    "(%u ms); with 2 control periods (%lld ms) at most 3 of them",
                    static_cast<long long>(c.heartbeat_consumer_ns / kMsNs), i,
                    unsigned(d.heartbeat_ms), static_cast<long long>(c.control_period_ns / kMsNs));
      return e;
    }
  }
  return nullptr;
}

CanopenWheelDrives::BringUp CanopenWheelDrives::fail(int i, const char* fmt, ...) {
  phase_ = Phase::Failed;
  result_ = DriveInitResult::failure(i, "?");
  int k = 0;
  if (i >= 0) {
    char who[64];
    k = std::snprintf(result_.what, DriveInitResult::kMaxText, "%s: ", label(i, who, sizeof who));
    if (k < 0 || k >= DriveInitResult::kMaxText) return BringUp::Failed;
  }
  std::va_list args;
  va_start(args, fmt);
  std::vsnprintf(result_.what + k, std::size_t(DriveInitResult::kMaxText - k), fmt, args);
  va_end(args);
  return BringUp::Failed;
}

DriveInitResult CanopenWheelDrives::init() {
  TimeNs last = clock_.now_ns();
  start_bring_up(last);
  BringUp s = poll_bring_up(last);
  int stalled = 0;
  while (s == BringUp::Running) {
    waiter_.wait(clock_.now_ns() + cfg_.bring_up_poll_ns);
    const TimeNs now = clock_.now_ns();
    // A waiter that lets no time pass would wait forever for timeouts that never come.
    stalled = now > last ? 0 : stalled + 1;
    if (stalled > 100'000) {
      fail(-1, "bring-up: the clock did not advance while waiting (BringUpWaiter, Clock)");
      break;
    }
    last = now;
    s = poll_bring_up(now);
  }
  return result_;
}

void CanopenWheelDrives::start_bring_up(TimeNs now) {
  const FlushOnExit flush{bus_};
  result_ = DriveInitResult::success();
  phase_ = Phase::Boot;
  phase_since_ns_ = now;
  if (config_error_[0] != '\0') {
    fail(-1, "config: %s", config_error_);
    return;
  }
  goal_ = Goal::Disabled;
  bus_down_ = false;
  next_master_hb_ns_ = now;
  last_sync_ns_ = now;
  heartbeats_ = HeartbeatMonitor{};
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    const std::size_t n_writes = d.n_writes;
    // Everything learnt from the drive goes; its SDO client and setup writes stay.
    d.psm = {};
    d.position = {};
    d.sw_heard = false;
    d.statusword = 0;
    d.velocity_counts = 0;
    d.latch = 0;
    d.latch_generic = false;
    d.reset_request = false;
    d.reset_since_ns = -1;
    d.enable_since_ns = -1;
    d.losses_seen = 0;
    d.next_write = 0;
    d.n_writes = n_writes;
    d.boot_ups_at_reset = 0;
    heartbeats_.watch(cfg_.drive[i].node, cfg_.heartbeat_consumer_ns);
    if (!send(nmt(NmtCommand::ResetCommunication, cfg_.drive[i].node), now)) {
      fail(i, "NMT reset communication not sent: %s", last_fault_);
      return;
    }
  }
}

CanopenWheelDrives::BringUp CanopenWheelDrives::poll_bring_up(TimeNs now) {
  const FlushOnExit flush{bus_};
  switch (phase_) {
    case Phase::Idle:
      return fail(-1, "bring-up not started (start_bring_up)");
    case Phase::Ready:
      return BringUp::Done;
    case Phase::Failed:
      return BringUp::Failed;
    default:
      break;
  }
  receive(now);
  master_heartbeat(now);
  if (bus_down_) return fail(-1, "bring-up: %s", last_fault_);
  char t[24];
  const TimeNs waited = now - phase_since_ns_;
  switch (phase_) {
    case Phase::Boot: {
      for (int i = 0; i < cfg_.wheels; ++i) {
        const HeartbeatMonitor::Node* hb = heartbeats_.find(cfg_.drive[i].node);
        if (hb->boot_ups > drive_[i].boot_ups_at_reset) continue;
        if (waited <= cfg_.boot_timeout_ns) return BringUp::Running;
        return fail(i, "no boot-up within %s after NMT reset communication",
                    seconds(cfg_.boot_timeout_ns, t, sizeof t));
      }
      phase_ = Phase::Configure;
      phase_since_ns_ = now;
      return poll_configure(now);
    }
    case Phase::Configure:
      return poll_configure(now);
    case Phase::Start: {
      for (int i = 0; i < cfg_.wheels; ++i) {
        const HeartbeatMonitor::Node* hb = heartbeats_.find(cfg_.drive[i].node);
        const bool operational =
            hb->last_ns >= phase_since_ns_ && hb->state == std::uint8_t(NmtState::Operational);
        if (operational) continue;
        if (waited <= cfg_.boot_timeout_ns) return BringUp::Running;
        return fail(i, "not operational within %s after NMT start (last heartbeat: %s)",
                    seconds(cfg_.boot_timeout_ns, t, sizeof t), nmt_state_name(hb->state));
      }
      phase_ = Phase::Enable;
      phase_since_ns_ = now;
      goal_ = Goal::Enabled;
      for (int i = 0; i < cfg_.wheels; ++i) {
        // A drive that powers up in Fault (an undervoltage at switch-on) gets one reset.
        drive_[i].reset_request = true;
        drive_[i].reset_since_ns = now;
      }
      return poll_power(now);
    }
    default:
      return poll_power(now);
  }
}

CanopenWheelDrives::BringUp CanopenWheelDrives::poll_configure(TimeNs now) {
  char t[24];
  bool done = true;
  for (int i = 0; i < cfg_.wheels; ++i) {
    Drive& d = drive_[i];
    SdoClient& sdo = *d.sdo;
    sdo.poll(now);
    if (sdo.busy()) {
      done = false;
      continue;
    }
    if (d.next_write > 0) {
      const SdoWrite& w = d.writes[d.next_write - 1];
      const SdoResult& r = sdo.result();
      switch (r.state) {
        case SdoState::Done:
          break;
        case SdoState::Aborted:
          return fail(i, "SDO write 0x%04X:%02X = %u (%s) aborted: 0x%08X %s", unsigned(w.index),
                      unsigned(w.subindex), unsigned(w.value), w.what, unsigned(r.abort_code),
                      sdo_abort_meaning(r.abort_code));
        case SdoState::TimedOut:
          return fail(i, "SDO write 0x%04X:%02X = %u (%s): no response within %s",
                      unsigned(w.index), unsigned(w.subindex), unsigned(w.value), w.what,
                      seconds(cfg_.sdo_timeout_ns, t, sizeof t));
        default:
          return fail(i, "SDO write 0x%04X:%02X (%s) failed: %s", unsigned(w.index),
                      unsigned(w.subindex), w.what, r.message);
      }
    }
    if (d.next_write < d.n_writes) {
      const SdoWrite& w = d.writes[d.next_write++];
      if (!sdo.start_download(w.index, w.subindex, w.value, w.size)) {
        return fail(i, "SDO write 0x%04X:%02X (%s) not sent: CAN send refused", unsigned(w.index),
                    unsigned(w.subindex), w.what);
      }
      done = false;
    }
  }
  if (!done) return BringUp::Running;
  for (int i = 0; i < cfg_.wheels; ++i) {
    if (!send(nmt(NmtCommand::Start, cfg_.drive[i].node), now)) {
      return fail(i, "NMT start not sent: %s", last_fault_);
    }
  }
  phase_ = Phase::Start;
  phase_since_ns_ = now;
  return BringUp::Running;
}

// Enable then disable every drive through its power state machine: a drive that will not
// enable is found here, naming its state, not at the first mission.
CanopenWheelDrives::BringUp CanopenWheelDrives::poll_power(TimeNs now) {
  watch_heartbeats(now);
  if (!exchange_pdos(now)) return fail(-1, "bring-up: %s", last_fault_);
  for (int i = 0; i < cfg_.wheels; ++i) {
    if (drive_[i].latch != 0) {
      phase_ = Phase::Failed;  // last_fault_ already names the drive
      result_ = DriveInitResult::failure(i, "%s", last_fault_);
      return BringUp::Failed;
    }
  }
  bool at_goal = true;
  for (int i = 0; i < cfg_.wheels; ++i) at_goal = at_goal && drive_[i].psm.at_goal();
  if (at_goal && phase_ == Phase::Enable) {
    goal_ = Goal::Disabled;
    phase_ = Phase::Disable;
    phase_since_ns_ = now;
    return BringUp::Running;
  }
  if (at_goal) {
    phase_ = Phase::Ready;
    return BringUp::Done;
  }
  // While enabling, check_faults()' enable timeout usually fires first (same message); this
  // bound ends both phases regardless.
  if (now - phase_since_ns_ <= cfg_.enable_timeout_ns) return BringUp::Running;
  char t[24];
  for (int i = 0; i < cfg_.wheels; ++i) {
    const cia402::PowerStateMachine& p = drive_[i].psm;
    if (p.at_goal()) continue;
    return fail(i, "stuck in %s, waiting for %s after %s", cia402::state_name(p.state()),
                cia402::state_name(p.awaiting()), seconds(cfg_.enable_timeout_ns, t, sizeof t));
  }
  return BringUp::Running;
}

}  // namespace carril::hal::canopen
