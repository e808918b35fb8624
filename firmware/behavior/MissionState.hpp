#pragma once
#include <cstdint>

#include "firmware/app/Faults.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// Behaviour states of the walking skeleton's follow_line mission.
enum class MissionState : std::uint8_t {
  Init,     // waiting for drives to enable and sensors to deliver
  Follow,   // tracking the tape
  Lost,     // tape not in view: turning toward where it was last seen
  End,      // end mark seen: driving onto it, then holding still
  Blocked,  // protective stop: something is right ahead
  Fault,    // latched fault: safe stop
  Count,
};

inline const char* state_name(MissionState s) {
  switch (s) {
    case MissionState::Init:
      return "INIT";
    case MissionState::Follow:
      return "FOLLOW";
    case MissionState::Lost:
      return "LOST";
    case MissionState::End:
      return "END";
    case MissionState::Blocked:
      return "BLOCKED";
    case MissionState::Fault:
      return "FAULT";
    case MissionState::Count:
      break;
  }
  return "?";
}

enum class EventKind : std::uint8_t { StateChange, Fault };

// One entry of the firmware's event log (read and printed outside the tick).
struct Event {
  hal::TimeNs t_ns = 0;
  EventKind kind = EventKind::StateChange;
  MissionState from = MissionState::Init, to = MissionState::Init;
  fw::Fault fault = fw::Fault::None;
  std::uint16_t code = 0;  // drive fault code, when fault == DriveFault
};

}  // namespace carril::fw
