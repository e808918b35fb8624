#pragma once
// One line of text for a firmware event, for logs printed outside the tick (simulator, robot).
#include <cstddef>
#include <cstdio>

#include "firmware/core/Faults.hpp"
#include "firmware/behavior/LineState.hpp"

namespace carril::fw {

// Writes "<t> s  ..." into buf; t_s is the event's time relative to whatever the caller chooses.
inline void format_event(const Event& e, double t_s, char* buf, std::size_t n) {
  switch (e.kind) {
    case EventKind::Fault:
      std::snprintf(buf, n, "%9.3f s  FAULT %s (code 0x%04X) in %s: safe stop", t_s,
                    fault_name(e.fault), unsigned(e.code), state_name(e.from));
      break;
    case EventKind::Phase:
      std::snprintf(buf, n, "%9.3f s    %s: %s", t_s, state_name(e.to), e.phase ? e.phase : "");
      break;
    case EventKind::StateChange:
      std::snprintf(buf, n, "%9.3f s  %s -> %s", t_s, state_name(e.from), state_name(e.to));
      break;
  }
}

}  // namespace carril::fw
