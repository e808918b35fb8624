#include "firmware/app/StatusReporter.hpp"

#include <cstdio>

namespace carril::fw {

void StatusReporter::format(const StatusSnapshot& s, char* buf, std::size_t n) {
  std::snprintf(buf, n,
                "status %9.3f s  %s %s/%s  fault %s  odom (%.2f, %.2f, %.2f)  ticks %llu "
                "(overruns %llu, max %.0f us)  frames %llu  scans %llu  events dropped %llu",
                double(s.t_ns) * 1e-9, mission_status_name(s.status), s.state, s.phase,
                fault_name(s.fault), s.odom.x, s.odom.y, s.odom.yaw,
                static_cast<unsigned long long>(s.ticks),
                static_cast<unsigned long long>(s.tick_overruns), s.tick_max_us,
                static_cast<unsigned long long>(s.frames), static_cast<unsigned long long>(s.scans),
                static_cast<unsigned long long>(s.events_dropped));
}

void StatusReporter::run() {
  if (!in_.fetch()) return;  // nothing new since the last line
  char line[320];
  format(in_.value(), line, sizeof line);
  out_.write_line(line);
  ++lines_;
}

}  // namespace carril::fw
