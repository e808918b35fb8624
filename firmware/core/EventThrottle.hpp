#pragma once
// Keeps a flood from pushing what matters out of an event log: faults always pass; other events
// (state changes, phases, overruns) pass at most `per_window` per window and the rest are only
// counted, so a robot flapping between two states, or overrunning every task, leaves room in the
// log for the fault that stopped it. Single-threaded, like the log it feeds.
#include <cstdint>

#include "firmware/core/EventLog.hpp"

namespace carril::fw {

class EventThrottle final : public EventSink {
 public:
  // out: the log; per_window events [events] per window_ns [ns] of event time.
  EventThrottle(EventSink& out, std::uint32_t per_window, hal::TimeNs window_ns)
      : out_(out), per_window_(per_window), window_ns_(window_ns) {}

  bool push(const Event& e) override {
    if (e.kind != EventKind::Fault && e.severity != Severity::Error) {
      if (e.t_ns < window_start_ns_ || e.t_ns - window_start_ns_ >= window_ns_) {
        window_start_ns_ = e.t_ns;
        in_window_ = 0;
      }
      if (in_window_ >= per_window_) {
        ++throttled_;
        return true;  // counted, not dropped from the log: nothing older was lost for it
      }
      ++in_window_;
    }
    return out_.push(e);
  }
  // Events counted but not logged, since construction [events].
  std::uint64_t throttled() const { return throttled_; }

 private:
  EventSink& out_;
  std::uint32_t per_window_;
  hal::TimeNs window_ns_;
  hal::TimeNs window_start_ns_ = 0;
  std::uint32_t in_window_ = 0;
  std::uint64_t throttled_ = 0;
};

}  // namespace carril::fw
