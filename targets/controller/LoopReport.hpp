#pragma once
// The real-time loop's figures, as carril_controller prints them on SIGUSR1 and on exit: how
// late the loop woke after each deadline (scheduling latency) and how long each tick computed.
// The loop thread fills them between ticks when asked (the histograms are its own); the slow
// rate group's thread prints them, so the control loop never writes to a terminal.
#include <atomic>
#include <cstdint>
#include <cstdio>

#include "firmware/core/LatencyStats.hpp"
#include "hal/Console.hpp"
#include "hal/TripleBuffer.hpp"

namespace carril::controller {

struct LoopFigures {
  std::uint64_t periods = 0;                                          // loop periods run
  std::uint64_t missed_deadlines = 0;                                 // periods lost to overruns
  double wake_p50_us = 0, wake_p99_us = 0, wake_max_us = 0;           // wake latency [us]
  double compute_p50_us = 0, compute_p99_us = 0, compute_max_us = 0;  // tick compute [us]
};

// "wake latency p50 12 us, p99 48 us, max 130 us; compute p50 ... " into buf.
inline void format_loop_figures(const LoopFigures& f, char* buf, std::size_t n) {
  std::snprintf(buf, n,
                "loop: periods %llu, missed deadlines %llu; wake latency p50 %.0f us, p99 %.0f "
                "us, max %.0f us; tick compute p50 %.1f us, p99 %.1f us, max %.1f us",
                static_cast<unsigned long long>(f.periods),
                static_cast<unsigned long long>(f.missed_deadlines), f.wake_p50_us, f.wake_p99_us,
                f.wake_max_us, f.compute_p50_us, f.compute_p99_us, f.compute_max_us);
}

// Fills LoopFigures from the loop's histograms (the loop thread, between ticks).
inline LoopFigures loop_figures(std::uint64_t periods, std::uint64_t missed,
                                const fw::LatencyStats& wake, double compute_p50_us,
                                double compute_p99_us, double compute_max_us) {
  LoopFigures f;
  f.periods = periods;
  f.missed_deadlines = missed;
  f.wake_p50_us = wake.percentile_us(0.50);
  f.wake_p99_us = wake.percentile_us(0.99);
  f.wake_max_us = wake.max_us();
  f.compute_p50_us = compute_p50_us;
  f.compute_p99_us = compute_p99_us;
  f.compute_max_us = compute_max_us;
  return f;
}

// Slow task: prints the figures the loop published, once each.
class LoopReportPrinter {
 public:
  LoopReportPrinter(hal::TripleBuffer<LoopFigures>& in, hal::Console& out) : in_(in), out_(out) {}
  void run() {
    if (!in_.fetch()) return;
    char line[256];
    format_loop_figures(in_.value(), line, sizeof line);
    out_.write_line(line);
    ++printed_;
  }
  std::uint64_t printed() const { return printed_; }

 private:
  hal::TripleBuffer<LoopFigures>& in_;
  hal::Console& out_;
  std::uint64_t printed_ = 0;
};

}  // namespace carril::controller
