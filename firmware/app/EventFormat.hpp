#pragma once
// One line of text for a firmware event, for logs printed outside the tick (simulator, robot).
#include <cstddef>
#include <cstdio>

#include "firmware/core/Event.hpp"

namespace carril::fw {

// Writes "<t> s  ..." into buf; t_s is the event's time relative to whatever the caller chooses.
inline void format_event(const Event& e, double t_s, char* buf, std::size_t n) {
  switch (e.kind) {
    case EventKind::Fault:
      std::snprintf(buf, n, "%9.3f s  FAULT %s (code 0x%04X) in %s: safe stop", t_s,
                    fault_name(e.fault), unsigned(e.code), e.from);
      break;
    case EventKind::Phase:
      std::snprintf(buf, n, "%9.3f s    %s: %s", t_s, e.to, e.phase ? e.phase : "");
      break;
    case EventKind::StateChange:
      std::snprintf(buf, n, "%9.3f s  %s -> %s", t_s, e.from, e.to);
      break;
    case EventKind::Overrun:
      std::snprintf(buf, n,
                    "%9.3f s  %s: task %s overran its %.0f us budget %u time%s (longest %.0f us)",
                    t_s, severity_name(e.severity), e.task, e.budget_us, unsigned(e.count),
                    e.count == 1 ? "" : "s", e.took_us);
      break;
  }
}

}  // namespace carril::fw
