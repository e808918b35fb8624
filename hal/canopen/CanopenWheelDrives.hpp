#pragma once
// The CANopen master as a WheelDrives backend: CiA 402 drives in profile velocity mode on one
// CanBus. init() brings every drive up (NMT reset communication, boot-up, the SDO writes of
// setup_writes(), NMT start, an enable and disable to prove the power state machine answers);
// sync() is one control period's bus exchange (bounded reads, heartbeat consumer, the power
// state machines, one RPDO per drive, SYNC, the master's heartbeat). Faults latch, stop every
// wheel and are named in last_fault(); see docs/can-protocol.md. Sized at construction: no heap,
// no blocking, no OS calls in sync().
#include <cstddef>
#include <cstdint>
#include <optional>

#include "hal/CanBus.hpp"
#include "hal/Clock.hpp"
#include "hal/WheelDrives.hpp"
#include "hal/canopen/Cia402.hpp"
#include "hal/canopen/DriveSetup.hpp"
#include "hal/canopen/Heartbeat.hpp"
#include "hal/canopen/SdoClient.hpp"

namespace carril::hal::canopen {

// Lets time pass while init() waits for the drives: sleeps on a robot; in tests it moves the
// bus, the scripted drives and a fake clock forward.
struct BringUpWaiter {
  virtual ~BringUpWaiter() = default;
  // Return at loop time `until` [ns] or later (earlier is allowed: init() just polls again).
  virtual void wait(TimeNs until) = 0;
};

// The waiter for a real loop: Clock::sleep_until_ns.
class ClockSleepWaiter final : public BringUpWaiter {
 public:
  explicit ClockSleepWaiter(Clock& clock) : clock_(clock) {}
  void wait(TimeNs until) override { clock_.sleep_until_ns(until); }

 private:
  Clock& clock_;
};

// Fault codes the master itself reports (a drive's own faults report its EMCY code).
constexpr std::uint16_t kFaultHeartbeatLost = 0x8130;   // = DriveFault::HeartbeatLost
constexpr std::uint16_t kFaultBusDown = 0x8100;         // bus-off or send refused
constexpr std::uint16_t kFaultEnableTimeout = 0xFF01;   // did not reach Operation enabled in time
constexpr std::uint16_t kFaultGeneric = 0x1000;         // Fault statusword without an EMCY
constexpr std::uint16_t kFaultRebooted = 0x6000;        // boot-up after bring-up: setup lost
constexpr std::uint16_t kFaultNotOperational = 0x8200;  // heartbeat: left Operational unasked
constexpr std::uint16_t kFaultFeedback = 0xFF02;        // TPDOs missing, malformed or implausible

struct CanopenConfig {
  static constexpr TimeNs kMs = 1'000'000;

  int wheels = 2;                            // drives on the bus, 1..kMaxWheels
  DriveSetup drive[kMaxWheels];              // per wheel, in kinematic order
  const char* name[kMaxWheels] = {};         // per wheel, for messages ("rear-left"); optional
  std::uint8_t master_node = 127;            // the master's node id (its heartbeat's COB-ID)
  TimeNs master_heartbeat_ns = 20 * kMs;     // the master's heartbeat period [ns]
  TimeNs control_period_ns = 10 * kMs;       // how often sync() is called [ns]
  TimeNs heartbeat_consumer_ns = 125 * kMs;  // a drive silent this long is lost [ns]; plus two
                                             // control periods at most 3 heartbeat periods
  TimeNs sdo_timeout_ns = 50 * kMs;          // per SDO response [ns]
  TimeNs boot_timeout_ns = 1000 * kMs;       // boot-up after reset, operational after start [ns]
  TimeNs enable_timeout_ns = 1000 * kMs;     // reaching Operation enabled (init and enable()) [ns]
  TimeNs bring_up_poll_ns = 10 * kMs;        // init()'s step: SDO polls, SYNCs while enabling [ns]
  int max_reads = 32;                        // frames read per sync() at most
  int feedback_missed_syncs = 10;            // consecutive SYNC periods with feedback missing,
                                             // malformed or implausible that latch a fault
  TimeNs backoff_min_ns = 100 * kMs;         // first bus probe after bus-off [ns], then doubling
  TimeNs backoff_max_ns = 2000 * kMs;        // ... up to this [ns]
};

// Totals since construction; they only grow.
struct CanopenCounters {
  std::uint64_t frames_read = 0;       // frames taken from the bus, error frames included
  std::uint64_t heartbeats = 0;        // from the drives, boot-ups included
  std::uint64_t tpdo1 = 0;             // statusword + velocity actual
  std::uint64_t tpdo2 = 0;             // position actual
  std::uint64_t sdo_responses = 0;     // from the drives' SDO servers
  std::uint64_t emcy = 0;              // emergency messages
  std::uint64_t error_frames = 0;      // error frames the controller reported
  std::uint64_t unknown_node = 0;      // CANopen frames of a node that is none of our drives
  std::uint64_t unknown_cob = 0;       // COB-IDs the master does not consume (or extended ids)
  std::uint64_t malformed = 0;         // our drives' frames with a wrong length, remote frames
  std::uint64_t heartbeat_losses = 0;  // drives found silent for the consumer time
  std::uint64_t feedback_bad = 0;      // SYNC periods a drive's feedback was missing, malformed
                                       // or implausible (each drive counted apart)
  std::uint64_t implausible = 0;       // TPDOs refused: speed beyond the limit, position jump
  std::uint64_t bus_offs = 0;          // bus-off or interface down events
  std::uint64_t probes = 0;            // bus probes after bus-off
  std::uint64_t send_refused = 0;      // send() returned false
  std::uint64_t fault_resets = 0;      // fault resets sent (rising edges of bit 7)
  std::uint64_t faults = 0;            // faults latched (each stopped every wheel)
  std::uint64_t syncs = 0;             // SYNC frames sent
};

// Hands what was sent to a batching transport to the wire at the end of a scope.
struct FlushOnExit {
  CanBus& bus;
  ~FlushOnExit() { bus.flush(); }
};

class CanopenWheelDrives final : public WheelDrives {
 public:
  // Holds the longest message, 166 bytes with every value at its widest.
  static constexpr int kMaxText = 256;

  enum class BringUp : std::uint8_t { Running, Done, Failed };

  // The config is checked here; a bad one makes init() fail naming the field.
  CanopenWheelDrives(CanBus& bus, Clock& clock, BringUpWaiter& waiter, const CanopenConfig& cfg);

  // Runs the bring-up state machine to its end, waiting between steps on the waiter.
  DriveInitResult init() override;
  int count() const override { return cfg_.wheels; }
  void enable() override;
  void disable() override;
  // Also the goal after every fault: resuming takes reset_faults() and enable().
  void quick_stop() override;
  // Clears the latched faults of drives heard since, and sends one fault reset to each drive
  // in Fault (one per call: a drive that faults again stays stopped).
  void reset_faults() override;
  void set_velocity(const float* radps, int n) override;
  void sync() override;
  void read(WheelFeedbackSet& out) const override;

  // Non-blocking bring-up, for a caller with its own loop: start, then poll until not Running.
  void start_bring_up(TimeNs now);
  BringUp poll_bring_up(TimeNs now);
  // The bring-up's outcome (ok until it failed).
  const DriveInitResult& bring_up_result() const { return result_; }

  // Empty when the config is valid, else what is wrong, naming the field.
  const char* config_error() const { return config_error_; }
  const CanopenCounters& counters() const { return counters_; }
  // The last fault, "drive 1 (node 3): EMCY 0x2310 continuous over-current"; "" before any.
  const char* last_fault() const { return last_fault_; }
  // The first fault since construction, kept whatever follows it; "" before any.
  const char* first_fault() const { return first_fault_; }
  // Increments with every fault latched, so a logger sees each new last_fault() once.
  std::uint64_t fault_seq() const { return counters_.faults; }
  // Whether the bus is considered down (bus-off, send refused) and being probed.
  bool bus_down() const { return bus_down_; }
  // Diagnostics of drive i.
  const cia402::PowerStateMachine& power_state(int i) const { return drive_[i].psm; }
  std::uint16_t last_emcy_code(int i) const { return drive_[i].emcy_code; }
  std::uint32_t emcy_count(int i) const { return drive_[i].emcy_count; }
  // The fault latched on drive i (0: none).
  std::uint16_t latched_fault(int i) const { return drive_[i].latch; }

 private:
  enum class Phase : std::uint8_t { Idle, Boot, Configure, Start, Enable, Disable, Ready, Failed };

  struct Drive {
    std::optional<SdoClient> sdo;
    SdoWrite writes[kMaxSetupWrites];
    std::size_t n_writes = 0;
    std::size_t next_write = 0;
    std::uint32_t boot_ups_at_reset = 0;
    cia402::PowerStateMachine psm;
    cia402::PositionUnwrapper position;
    bool sw_heard = false;
    std::uint16_t statusword = 0;
    std::int32_t velocity_counts = 0;
    TimeNs stamp_ns = 0;
    float target_radps = 0.0F;
    std::uint16_t emcy_code = 0;    // last EMCY's error code
    std::uint32_t emcy_count = 0;   // EMCYs received
    std::uint16_t latch = 0;        // latched fault code; 0 none
    TimeNs latch_ns = 0;            // when [ns]
    bool latch_generic = false;     // latched on a Fault statusword alone (an EMCY may name it)
    bool reset_request = false;     // one fault reset asked for, not yet sent
    TimeNs reset_since_ns = -1;     // a reset asked for at [ns]: a Fault does not latch until
                                    // the drive had enable_timeout_ns to leave it; -1 none
    std::uint32_t losses_seen = 0;  // heartbeat losses already latched
    TimeNs enable_since_ns = -1;    // when the current enable began [ns]; -1 not enabling
    // Feedback supervision, per SYNC period (see supervise_feedback()).
    bool tpdo1_fresh = false;         // a valid TPDO1 answered the last SYNC
    bool tpdo2_fresh = false;         // a valid TPDO2 answered the last SYNC
    const char* bad_why = nullptr;    // this period's malformed or implausible frame; null none
    int bad_periods = 0;              // consecutive bad periods
    const char* last_bad = "";        // what the last bad period lacked, for the fault message
    bool position_heard = false;      // raw_position holds a reading
    std::int32_t raw_position = 0;    // the last position actual [counts], for the jump check
    TimeNs raw_position_sync_ns = 0;  // the SYNC it answered [ns]
  };

  const char* validate();
  // "drive 1 (rear-left, node 3)" into buf.
  const char* label(int i, char* buf, std::size_t n) const;
  // Ends the bring-up: result_ names drive i (-1: none) and what failed.
  BringUp fail(int i, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

  void receive(TimeNs now);
  void dispatch(const CanFrame& f, TimeNs now);
  int drive_of(std::uint8_t node) const;
  void watch_heartbeats(TimeNs now);
  // Power state machines, RPDOs, SYNC; false when the bus refused a frame.
  bool exchange_pdos(TimeNs now);
  void master_heartbeat(TimeNs now);
  bool send(const CanFrame& f, TimeNs now);
  void bus_down(TimeNs now, const char* why);
  void probe(TimeNs now);
  // Latches fault `code` on drive i and stops every wheel; `text` completes last_fault().
  void latch(int i, std::uint16_t code, TimeNs now, const char* fmt, ...)
      __attribute__((format(printf, 5, 6)));
  // last_fault_ was just written: the first one is kept in first_fault_.
  void keep_first_fault();
  cia402::Goal goal_of(int i) const;

  BringUp poll_configure(TimeNs now);
  BringUp poll_power(TimeNs now);
  void check_faults(TimeNs now);
  // One SYNC period's verdict on each drive's feedback: bad_periods grows while it is
  // missing, malformed or implausible, and at feedback_missed_syncs the drive faults.
  void supervise_feedback(TimeNs now);
  // A position actual of drive i: false when it jumped further than the speed limit allows.
  bool plausible_position(Drive& d, int i, std::int32_t counts) const;
  bool any_latch() const;

  CanBus& bus_;
  Clock& clock_;
  BringUpWaiter& waiter_;
  CanopenConfig cfg_;
  char config_error_[kMaxText] = {};
  Drive drive_[kMaxWheels];
  HeartbeatMonitor heartbeats_;
  CanopenCounters counters_;
  char last_fault_[kMaxText] = {};
  char first_fault_[kMaxText] = {};

  Phase phase_ = Phase::Idle;
  TimeNs phase_since_ns_ = 0;
  DriveInitResult result_;
  cia402::Goal goal_ = cia402::Goal::Disabled;
  TimeNs next_master_hb_ns_ = 0;
  TimeNs last_sync_ns_ = 0;
  bool sync_outstanding_ = false;  // a SYNC went out in Ready and its TPDOs are due
  bool bus_down_ = false;
  TimeNs backoff_ns_ = 0;
  TimeNs next_probe_ns_ = 0;
};

}  // namespace carril::hal::canopen
