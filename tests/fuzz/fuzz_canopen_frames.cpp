// Fuzz target: the CANopen frame decoders (hal/canopen/Frames: heartbeat, EMCY, TPDO1/2), what
// the master does with what they decode (hal/canopen/Cia402: statusword, power state machine,
// position unwrapping; Heartbeat: the consumer) and the text tables (EMCY meanings, SDO abort
// meanings, NMT state names). Input: a byte selecting the watched node, then frames
// (FuzzFrames.hpp) each followed by a 2-byte time step [ms].
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "FuzzFrames.hpp"
#include "hal/canopen/Cia402.hpp"
#include "hal/canopen/Frames.hpp"
#include "hal/canopen/Heartbeat.hpp"
#include "hal/canopen/SdoAbort.hpp"

namespace co = carril::hal::canopen;
namespace cia402 = carril::hal::cia402;

namespace {

// A table lookup must give static text.
void check_text(const char* s) {
  if (s == nullptr || std::strlen(s) == 0) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  carril::fuzz::ByteReader in(data, size);
  const std::uint8_t node = static_cast<std::uint8_t>(in.u8() % 129);
  co::HeartbeatMonitor hb;
  hb.watch(node, 100'000'000);  // false for 0 and 128: then every heartbeat is unknown
  hb.watch(static_cast<std::uint8_t>(node % 127 + 1), 50'000'000);
  cia402::PowerStateMachine psm;
  cia402::PositionUnwrapper position;
  const cia402::DriveUnits units;
  carril::hal::TimeNs now = 0;
  while (in.remaining() > 0) {
    const carril::hal::CanFrame f = carril::fuzz::read_frame(in);
    now += carril::hal::TimeNs{in.u16()} * 1'000'000;
    std::uint8_t hb_node = 0, state = 0;
    if (co::decode_heartbeat(f, hb_node, state)) check_text(co::nmt_state_name(state));
    co::Emcy emcy;
    if (co::decode_emcy(f, emcy)) check_text(co::emcy_meaning(emcy.error_code));
    check_text(carril::hal::sdo_abort_meaning(co::get_u32(f.data + 4)));
    std::uint16_t sw = 0;
    std::int32_t velocity = 0, counts = 0;
    if (co::decode_tpdo1(f, node, sw, velocity)) {
      check_text(cia402::state_name(cia402::decode_statusword(sw)));
      psm.step(sw, static_cast<cia402::Goal>(f.data[7] % 3), (f.data[6] & 1) != 0);
      check_text(cia402::state_name(psm.state()));
      (void)cia402::to_wheel_radps(velocity, units);
    }
    if (co::decode_tpdo2(f, node, counts)) {
      position.add(counts);
      (void)position.wheel_rad(units);
    }
    hb.on_frame(f, now);
    hb.poll(now);
  }
  return 0;
}
