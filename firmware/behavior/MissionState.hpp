#pragma once
#include <cstdint>

#include "firmware/core/Faults.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// Behaviour states of the follow_line mission.
enum class MissionState : std::uint8_t {
  Start,   // wait for drives and sensors; turn to find the tape; drive onto it and align
  Follow,  // track the tape with the mission's strategy
  Search,  // tape lost: turn 90 deg left, 180 deg right, then 90 deg more to head back
  Avoid,   // obstacle on the tape: stop, align with the tape, pass it, rejoin beyond
  End,     // end mark reached: drive onto it and stop
  Fault,   // latched fault: safe stop
  Count,
};

inline const char* state_name(MissionState s) {
  switch (s) {
    case MissionState::Start:
      return "START";
    case MissionState::Follow:
      return "FOLLOW";
    case MissionState::Search:
      return "SEARCH";
    case MissionState::Avoid:
      return "AVOID";
    case MissionState::End:
      return "END";
    case MissionState::Fault:
      return "FAULT";
    case MissionState::Count:
      break;
  }
  return "?";
}

enum class EventKind : std::uint8_t { StateChange, Fault, Phase };

// One entry of the firmware's event log (read and printed outside the tick).
struct Event {
  hal::TimeNs t_ns = 0;
  EventKind kind = EventKind::StateChange;
  MissionState from = MissionState::Start, to = MissionState::Start;
  fw::Fault fault = fw::Fault::None;
  std::uint16_t code = 0;       // drive fault code, when fault == DriveFault
  const char* phase = nullptr;  // sub-state entered, for EventKind::Phase (static string)
};

}  // namespace carril::fw
