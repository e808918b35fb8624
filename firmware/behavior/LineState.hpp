#pragma once
#include <cstdint>

namespace carril::fw {

// States of the follow_line mission's state machine (LineBehavior).
enum class LineState : std::uint8_t {
  Start,   // wait for drives and sensors; turn to find the tape; drive onto it and align
  Follow,  // track the tape with the mission's strategy
  Search,  // tape lost: turn 90 deg left, 180 deg right, then 90 deg more to head back
  Avoid,   // obstacle on the tape: stop, align with the tape, pass it, rejoin beyond
  End,     // end mark reached: drive onto it and stop
  Fault,   // latched fault: safe stop
  Count,
};

inline const char* state_name(LineState s) {
  switch (s) {
    case LineState::Start:
      return "START";
    case LineState::Follow:
      return "FOLLOW";
    case LineState::Search:
      return "SEARCH";
    case LineState::Avoid:
      return "AVOID";
    case LineState::End:
      return "END";
    case LineState::Fault:
      return "FAULT";
    case LineState::Count:
      break;
  }
  return "?";
}

}  // namespace carril::fw
