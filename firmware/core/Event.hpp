#pragma once
// One entry of the firmware's event log: written inside the tick, read and printed outside it.
// Generic over missions: states and phases are names (static strings) that the mission reports.
#include <cstdint>

#include "firmware/core/Faults.hpp"
#include "firmware/core/Severity.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

enum class EventKind : std::uint8_t {
  StateChange,  // the mission moved from state `from` to state `to`
  Phase,        // the mission entered phase `phase` of state `to`
  Fault,        // fault `fault` latched in state `from`: safe stop
  Overrun,      // task `task` overran its time budget (throttled; `count` overruns since last)
};

struct Event {
  hal::TimeNs t_ns = 0;
  EventKind kind = EventKind::StateChange;
  Severity severity = Severity::Info;
  const char* from = "";  // state names (static strings)
  const char* to = "";
  const char* phase = nullptr;  // EventKind::Phase: the phase entered (static string)
  Fault fault = Fault::None;
  std::uint16_t code = 0;   // drive fault code, when fault == DriveFault
  const char* task = "";    // EventKind::Overrun: the task
  std::uint32_t count = 0;  // EventKind::Overrun: overruns reported by this event
  double took_us = 0.0;     // EventKind::Overrun: the longest of them [us]
  double budget_us = 0.0;   // EventKind::Overrun: the task's budget [us]
};

}  // namespace carril::fw
