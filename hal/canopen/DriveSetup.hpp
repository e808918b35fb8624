#pragma once
// What the master writes into each drive at bring-up, by SDO, in order (CiA 301 and CiA 402):
// profile velocity mode, the ramps, the quick stop option, the heartbeats (the drive watches the
// master's, so it stops on its own if the master dies), and the PDO mapping, every PDO sent and
// applied on SYNC. Pure data: the SDO client carries it out.
#include <cstddef>
#include <cstdint>

#include "hal/canopen/Cia402.hpp"

namespace carril::hal::canopen {

struct DriveSetup {
  std::uint8_t node = 1;                  // the drive's node id (1 to 127)
  cia402::DriveUnits units;               // encoder counts per motor revolution, gear ratio
  double accel_radps2 = 25.0;             // profile acceleration 0x6083 [wheel rad/s^2]
  double decel_radps2 = 25.0;             // profile deceleration 0x6084 [wheel rad/s^2]
  double quick_stop_decel_radps2 = 50.0;  // quick stop deceleration 0x6085 [wheel rad/s^2]
  std::uint16_t heartbeat_ms = 50;        // the drive's heartbeat period 0x1017 [ms]
  std::uint8_t master_node = 127;         // the master's node id, whose heartbeat the drive watches
  std::uint16_t master_timeout_ms = 150;  // consumer time 0x1016 for it [ms]
  double max_wheel_radps = 30.0;          // feedback faster than this is implausible [wheel rad/s]
  bool inverted = false;  // mounted mirrored: the master negates speeds and positions both ways
};

// One expedited SDO download.
struct SdoWrite {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint32_t value = 0;
  std::uint8_t size = 4;  // bytes: 1, 2 or 4
  const char* what = "";  // what it sets, for a bring-up error ("RPDO1 mapping entry 1")
};

constexpr std::size_t kMaxSetupWrites = 40;

// The writes for `s`, in order, into out[0..kMaxSetupWrites); returns how many.
std::size_t setup_writes(const DriveSetup& s, SdoWrite* out);

// Quick stop option code 6: slow down on the quick stop ramp and stay in Quick stop active (the
// drive holds still until the master disables it).
constexpr std::int16_t kQuickStopHold = 6;
// Profile velocity mode, object 0x6060.
constexpr std::int8_t kProfileVelocityMode = 3;

}  // namespace carril::hal::canopen
