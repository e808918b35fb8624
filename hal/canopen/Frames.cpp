#include "hal/canopen/Frames.hpp"

namespace carril::hal::canopen {

namespace {
// A data frame with a standard identifier (the only kind CANopen uses).
bool plain(const CanFrame& f) {
  return !f.extended && !f.rtr && !f.error;
}

bool valid_node(std::uint32_t node) {
  return node >= 1 && node <= kMaxNodeId;
}
}  // namespace

const char* nmt_state_name(std::uint8_t state) {
  switch (state) {
    case 0x00:
      return "boot-up";
    case 0x04:
      return "stopped";
    case 0x05:
      return "operational";
    case 0x7F:
      return "pre-operational";
    default:
      return "unknown NMT state";
  }
}

CanFrame nmt(NmtCommand cmd, std::uint8_t node) {
  CanFrame f;
  f.id = kNmtId;
  f.len = 2;
  f.data[0] = static_cast<std::uint8_t>(cmd);
  f.data[1] = node;
  return f;
}

CanFrame sync_frame() {
  CanFrame f;
  f.id = kSyncId;
  f.len = 0;
  return f;
}

CanFrame heartbeat(std::uint8_t node, NmtState state) {
  CanFrame f;
  f.id = kHeartbeatBase + node;
  f.len = 1;
  f.data[0] = static_cast<std::uint8_t>(state);
  return f;
}

bool decode_heartbeat(const CanFrame& f, std::uint8_t& node, std::uint8_t& state) {
  if (!plain(f) || f.len != 1 || f.id < kHeartbeatBase + 1 || f.id > kHeartbeatBase + kMaxNodeId) {
    return false;
  }
  node = static_cast<std::uint8_t>(f.id - kHeartbeatBase);
  state = f.data[0] & 0x7FU;  // bit 7 is the toggle bit of node guarding, not state
  return true;
}

bool decode_emcy(const CanFrame& f, Emcy& out) {
  if (!plain(f) || f.len != 8 || f.id <= kEmcyBase || !valid_node(f.id - kEmcyBase)) return false;
  out.node = static_cast<std::uint8_t>(f.id - kEmcyBase);
  out.error_code = get_u16(f.data);
  out.error_register = f.data[2];
  for (int i = 0; i < 5; ++i) out.vendor[i] = f.data[3 + i];
  return true;
}

const char* emcy_meaning(std::uint16_t c) {
  switch (c) {  // specific codes first (CiA 402 annex), then the classes of CiA 301 table 21
    case 0x0000:
      return "error reset or no error";
    case 0x2310:
      return "continuous over-current";
    case 0x2320:
      return "short circuit or earth leakage";
    case 0x3210:
      return "DC link over-voltage";
    case 0x3220:
      return "DC link under-voltage";
    case 0x4310:
      return "drive temperature too high";
    case 0x7121:
      return "motor blocked";
    case 0x7305:
      return "incremental sensor 1 fault";
    case 0x8110:
      return "CAN overrun (objects lost)";
    case 0x8120:
      return "CAN in error passive mode";
    case 0x8130:
      return "life guard or heartbeat error";
    case 0x8140:
      return "recovered from bus off";
    case 0x8611:
      return "following error";
    default:
      break;
  }
  switch (c & 0xF000U) {
    case 0x1000:
      return "generic error";
    case 0x2000:
      return "current";
    case 0x3000:
      return "voltage";
    case 0x4000:
      return "temperature";
    case 0x5000:
      return "device hardware";
    case 0x6000:
      return "device software";
    case 0x7000:
      return "additional modules";
    case 0x8000:
      return "monitoring (communication, protocol)";
    case 0x9000:
      return "external error";
    case 0xF000:
      return "additional functions or device specific";
    default:
      return "unknown error code";
  }
}

CanFrame rpdo1(std::uint8_t node, std::uint16_t controlword, std::int32_t target_velocity) {
  CanFrame f;
  f.id = kRpdo1Base + node;
  f.len = 6;
  put_u16(f.data, controlword);
  put_u32(f.data + 2, static_cast<std::uint32_t>(target_velocity));
  return f;
}

bool decode_tpdo1(const CanFrame& f, std::uint8_t node, std::uint16_t& statusword,
                  std::int32_t& velocity_actual) {
  if (!plain(f) || f.id != kTpdo1Base + node || f.len != 6) return false;
  statusword = get_u16(f.data);
  velocity_actual = static_cast<std::int32_t>(get_u32(f.data + 2));
  return true;
}

bool decode_tpdo2(const CanFrame& f, std::uint8_t node, std::int32_t& position_actual) {
  if (!plain(f) || f.id != kTpdo2Base + node || f.len != 4) return false;
  position_actual = static_cast<std::int32_t>(get_u32(f.data));
  return true;
}

}  // namespace carril::hal::canopen
