#pragma once
// Runs a step function at a fixed rate on absolute deadlines (next += period), so jitter and
// overruns do not accumulate into drift. An overrun (a step finishing after its next deadline)
// is counted and the schedule skips the missed periods instead of bursting to catch up.
#include <cstdint>

#include "firmware/core/LatencyStats.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

struct LoopStats {
  std::uint64_t periods = 0;
  std::uint64_t missed_deadlines = 0;  // periods skipped because a step overran
};

class FixedRateLoop {
 public:
  FixedRateLoop(hal::Clock& clock, hal::TimeNs period_ns) : clock_(clock), period_ns_(period_ns) {}

  // Calls step(ctx) every period until it returns false or max_periods have run (0 = no limit).
  template <typename Step>
  LoopStats run(Step&& step, std::uint64_t max_periods = 0) {
    LoopStats st;
    hal::TimeNs next = clock_.now_ns();
    while (max_periods == 0 || st.periods < max_periods) {
      const bool go_on = step();
      ++st.periods;
      if (!go_on) break;
      next += period_ns_;
      const hal::TimeNs now = clock_.now_ns();
      if (now > next) {
        // Deadlines passed while the step ran; one met exactly (now == deadline) still counts.
        const hal::TimeNs late = now - next;
        const auto skipped = static_cast<std::uint64_t>((late + period_ns_ - 1) / period_ns_);
        st.missed_deadlines += skipped;
        missed_ += skipped;
        next += static_cast<hal::TimeNs>(skipped) * period_ns_;
      }
      clock_.sleep_until_ns(next);
      // How late the OS woke us: the scheduling latency a real-time loop is judged by.
      const hal::TimeNs woke = clock_.now_ns() - next;
      wake_.add(woke > 0 ? woke : 0);
    }
    return st;
  }

  // Wake latency: how long after each deadline the loop ran again [1 us bins, up to 8 ms exact].
  const LatencyStats& wake_latency() const { return wake_; }
  // Deadlines missed since construction (also while run() is under way).
  std::uint64_t missed_deadlines() const { return missed_; }

 private:
  hal::Clock& clock_;
  hal::TimeNs period_ns_;
  LatencyStats wake_{1000};
  std::uint64_t missed_ = 0;
};

}  // namespace carril::fw
