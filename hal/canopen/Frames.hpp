#pragma once
// CANopen (CiA 301) frames the master sends and reads, encoded and decoded as plain functions on
// hal::CanFrame: NMT commands, SYNC, heartbeats, EMCY, and the process data of a CiA 402 drive in
// profile velocity mode. A decoder returns false for a frame of another kind, another node or the
// wrong length: such frames are counted by the caller and never acted on.
#include <cstdint>

#include "hal/CanBus.hpp"

namespace carril::hal::canopen {

constexpr std::uint8_t kMaxNodeId = 127;

// Function codes (the COB-ID is function + node id).
constexpr std::uint32_t kNmtId = 0x000;
constexpr std::uint32_t kSyncId = 0x080;
constexpr std::uint32_t kEmcyBase = 0x080;
constexpr std::uint32_t kTpdo1Base = 0x180;  // drive -> master: statusword, velocity actual
constexpr std::uint32_t kRpdo1Base = 0x200;  // master -> drive: controlword, target velocity
constexpr std::uint32_t kTpdo2Base = 0x280;  // drive -> master: position actual
constexpr std::uint32_t kHeartbeatBase = 0x700;

// NMT command specifiers (CiA 301, 7.2.8.3.1).
enum class NmtCommand : std::uint8_t {
  Start = 0x01,
  Stop = 0x02,
  EnterPreOperational = 0x80,
  ResetNode = 0x81,
  ResetCommunication = 0x82,
};

// NMT states as a heartbeat reports them.
enum class NmtState : std::uint8_t {
  BootUp = 0x00,
  Stopped = 0x04,
  Operational = 0x05,
  PreOperational = 0x7F,
};
const char* nmt_state_name(std::uint8_t state);

// NMT command to `node` (0: every node).
CanFrame nmt(NmtCommand cmd, std::uint8_t node);
CanFrame sync_frame();
// The heartbeat (or boot-up message, state BootUp) of node `node`.
CanFrame heartbeat(std::uint8_t node, NmtState state);
// A heartbeat or boot-up message: its node and the state byte.
bool decode_heartbeat(const CanFrame& f, std::uint8_t& node, std::uint8_t& state);

// An emergency message (CiA 301, 7.2.7).
struct Emcy {
  std::uint8_t node = 0;
  std::uint16_t error_code = 0;     // CiA 301 / CiA 402 error code
  std::uint8_t error_register = 0;  // object 0x1001
  std::uint8_t vendor[5] = {};      // manufacturer-specific field
};
bool decode_emcy(const CanFrame& f, Emcy& out);
// The meaning of an EMCY error code: its class from CiA 301 table 21, or the CiA 402 code where
// it names one ("0x2310 continuous over-current", ...).
const char* emcy_meaning(std::uint16_t error_code);

// RPDO1 of a profile-velocity drive: controlword 0x6040 and target velocity 0x60FF [counts/s].
CanFrame rpdo1(std::uint8_t node, std::uint16_t controlword, std::int32_t target_velocity);
// TPDO1: statusword 0x6041 and velocity actual 0x606C [counts/s].
bool decode_tpdo1(const CanFrame& f, std::uint8_t node, std::uint16_t& statusword,
                  std::int32_t& velocity_actual);
// TPDO2: position actual 0x6064 [counts].
bool decode_tpdo2(const CanFrame& f, std::uint8_t node, std::int32_t& position_actual);

// Little-endian field access (CANopen's byte order).
inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
         (std::uint32_t(p[3]) << 24);
}

}  // namespace carril::hal::canopen
