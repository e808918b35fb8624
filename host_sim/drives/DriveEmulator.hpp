#pragma once
// One emulated CANopen wheel drive (CiA 301 + CiA 402 profile velocity), the other side of the
// master in docs/can-protocol.md: NMT with boot-up, an SDO server for the objects of
// ObjectDictionary, RPDO1/TPDO1/TPDO2 on SYNC, heartbeat producer and consumer (it stops its
// wheel on its own when the master's heartbeat stops), EMCY, the CiA 402 power state machine,
// the 0x6083/0x6084/0x6085 ramps and a first-order velocity loop: the emulator owns the motor
// model, and the simulator drives its wheel at wheel_speed_radps(). Deterministic: it acts only
// in step(), on the caller's time. Fault injection on command. No heap, no OS calls.
#include <cstdint>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"
#include "hal/canopen/Cia402.hpp"
#include "hal/canopen/DriveSetup.hpp"
#include "hal/canopen/Frames.hpp"
#include "hal/canopen/SdoClient.hpp"
#include "host_sim/drives/ObjectDictionary.hpp"
#include "host_sim/drives/SdoServer.hpp"

namespace carril::sim {

// EMCY error codes the emulator sends by itself.
constexpr std::uint16_t kEmcyHeartbeatLost = 0x8130;  // life guard or heartbeat error
constexpr std::uint16_t kEmcyPdoLength = 0x8210;      // PDO not processed: length error
constexpr std::uint16_t kEmcyErrorReset = 0x0000;     // error reset (fault cleared)

class DriveEmulator : private SdoServer::Hooks {
 public:
  using State = hal::cia402::State;
  using NmtState = hal::canopen::NmtState;

  struct Config {
    std::uint8_t node = 1;          // node id, 1 to 127
    hal::cia402::DriveUnits units;  // counts per motor revolution, gear ratio
    double velocity_tau_s = 0.02;   // velocity loop time constant [s]; 0: follows the ramp
    double coast_tau_s = 0.5;       // speed decay without torque (friction) [s]; 0: stops at once
    double target_window_radps = 0.05;         // statusword bit 10 window [wheel rad/s]
    std::int64_t initial_position_counts = 0;  // position actual at power-on [counts]
  };

  // What a silenced drive stops sending (set_silence()).
  enum class Silence : std::uint8_t {
    None,       // sends everything
    Heartbeat,  // no heartbeats (nor boot-ups); PDOs, SDO answers, EMCY go on (a broken producer)
    Bus,        // sends nothing at all (a dead transmitter); it still receives and acts
  };

  // Totals since construction [frames or events]; they only grow.
  struct Counters {
    std::uint64_t frames_received = 0;   // taken from the bus
    std::uint64_t frames_handled = 0;    // acted on
    std::uint64_t frames_unknown = 0;    // not for this drive: a COB-ID it does not listen to
                                         // (other nodes' frames too), remote/extended/error
    std::uint64_t frames_malformed = 0;  // for this drive, with the wrong length
    std::uint64_t frames_ignored_in_state = 0;  // for this drive, not in its NMT state (PDOs
                                                // outside Operational, SDO while Stopped)
    std::uint64_t frames_sent = 0;              // accepted by the bus
    std::uint64_t frames_refused = 0;           // refused by the bus (queue full, bus-off)
    std::uint64_t frames_silenced = 0;          // not sent because of set_silence()
    std::uint64_t frames_injected = 0;          // corrupt or unknown frames sent on purpose
    std::uint64_t syncs = 0;                    // SYNCs handled in Operational
    std::uint64_t rpdos_applied = 0;            // RPDO1s applied at a SYNC
    std::uint64_t tpdos_sent = 0;               // TPDO1 and TPDO2
    std::uint64_t heartbeats_sent = 0;          // boot-ups excluded
    std::uint64_t boot_ups_sent = 0;
    std::uint64_t emcys_sent = 0;
    std::uint64_t sdo_requests = 0;
    std::uint64_t sdo_aborts_sent = 0;
    std::uint64_t nmt_transitions = 0;
    std::uint64_t state_transitions = 0;    // CiA 402 power state changes
    std::uint64_t transitions_refused = 0;  // refused by refuse_enable()
    std::uint64_t faults = 0;               // entries into Fault reaction / Fault
    std::uint64_t fault_resets = 0;         // Fault -> Switch on disabled
    std::uint64_t master_heartbeat_losses = 0;
  };

  // The drive talks on `bus` (one endpoint of a LoopbackCanBus, or a SocketCAN port).
  DriveEmulator(hal::CanBus& bus, const Config& cfg);

  // One simulation step at time `now` [ns], `dt_s` [s] after the last: handles every received
  // frame (power-on boot-up on the first step), watches the master's heartbeat, runs the ramps,
  // the velocity loop and the state machine, sends heartbeats.
  void step(hal::TimeNs now, double dt_s);
  // Power off and on: every object to its default, boot-up at the next step. Injected faults
  // and the persistent fault stay (they are the hardware's).
  void power_cycle();

  // The wheel speed the motor produces [wheel rad/s], for the simulator's wheel.
  double wheel_speed_radps() const;
  // The wheel angle since power-on [rad] (from initial_position_counts).
  double wheel_position_rad() const;
  // Whether the motor produces torque (Operation enabled, Quick stop active, Fault reaction).
  bool torque_on() const;

  State state() const { return state_; }
  NmtState nmt_state() const { return nmt_; }
  std::uint16_t statusword() const;
  std::uint16_t error_code() const { return error_code_; }  // 0x603F, 0 when no fault
  bool master_heartbeat_lost() const { return master_lost_; }
  const ObjectDictionary& od() const { return od_; }
  const Counters& counters() const { return counters_; }
  const Config& config() const { return cfg_; }

  // Fault injection.
  void set_silence(Silence s) { silence_ = s; }
  // EMCY `error_code` and a fault (Fault reaction active on the quick stop ramp, then Fault).
  // `persistent`: fault resets are refused until clear_persistent_fault().
  void inject_fault(std::uint16_t error_code, bool persistent = false);
  void clear_persistent_fault() { fault_persistent_ = false; }
  // The drive refuses to leave `stuck_in` toward Operation enabled (Not ready to switch on:
  // never reaches Switch on disabled after power-on); State::Unknown lifts it.
  void refuse_enable(State stuck_in) { stuck_in_ = stuck_in; }
  // SDO accesses to index:subindex (SdoServer::kAnySubindex: all) answered with abort `code`.
  bool inject_sdo_abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) {
    return sdo_.inject_abort(index, subindex, code);
  }
  void clear_sdo_aborts() { sdo_.clear_injected_aborts(); }
  // At the next `syncs` SYNCs, TPDO1 and TPDO2 go out one byte short (5 and 3 bytes).
  void inject_corrupt_frames(int syncs) { corrupt_left_ = syncs; }
  // At the next `syncs` SYNCs, one frame with a COB-ID nobody configured (0x380 + node, TPDO3,
  // 8 bytes) is sent after the TPDOs.
  void inject_unknown_frames(int syncs) { unknown_left_ = syncs; }

 private:
  std::uint32_t check_download(const OdEntry& e, std::uint32_t value) override;
  void after_download(const OdEntry& e) override;

  void handle(const hal::CanFrame& f);
  void handle_nmt(const hal::CanFrame& f);
  void handle_sync();
  void boot();
  void set_nmt(NmtState s);
  void leave_operational();
  void send(const hal::CanFrame& f, bool heartbeat = false);
  void send_emcy(std::uint16_t code);
  void apply_controlword(std::uint16_t cw);
  void set_state(State s);
  void enter_fault(std::uint16_t code);
  void watch_master();
  void move(double dt_s);
  void send_heartbeat_if_due();
  void send_tpdos();
  void publish();  // the dynamic objects (0x6041, 0x6064, 0x606C...) from the model
  bool pdo_valid(std::uint16_t comm_index) const;
  double counts_per_rad() const;

  hal::CanBus& bus_;
  Config cfg_;
  ObjectDictionary od_;
  SdoServer sdo_;
  Counters counters_;

  hal::TimeNs now_ = 0;
  bool boot_pending_ = true;
  NmtState nmt_ = NmtState::BootUp;  // BootUp: initialising, until the boot-up is sent
  State state_ = State::NotReadyToSwitchOn;
  std::uint16_t last_cw_ = 0;
  bool rpdo_pending_ = false;
  std::uint16_t rpdo_cw_ = 0;
  std::int32_t rpdo_target_ = 0;
  std::uint32_t tpdo_syncs_[2] = {};  // SYNCs since the last TPDO1/TPDO2 (transmission type)

  double demand_cps_ = 0.0;  // ramp output, velocity demand 0x606B [counts/s]
  double actual_cps_ = 0.0;  // motor speed 0x606C [counts/s]
  double position_counts_ = 0.0;

  hal::TimeNs next_heartbeat_ = 0;
  bool master_heard_ = false;
  bool master_lost_ = false;
  hal::TimeNs master_last_ = 0;

  std::uint16_t error_code_ = 0;
  bool fault_persistent_ = false;

  Silence silence_ = Silence::None;
  State stuck_in_ = State::Unknown;
  int corrupt_left_ = 0;
  int unknown_left_ = 0;
};

// The name of a silence mode: "none", "heartbeat", "bus".
const char* silence_name(DriveEmulator::Silence s);

}  // namespace carril::sim
