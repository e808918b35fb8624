#include "firmware/core/SlowRateGroup.hpp"

#include <cmath>

namespace carril::fw {

Status SlowRateGroup::init(double rate_hz, EventSink* events, double overrun_throttle_s) {
  cycle_stats_.reset();
  cycles_ = 0;
  late_cycles_ = 0;
  period_ns_ = 0;
  const Status s = table_.init(rate_hz, events, overrun_throttle_s);
  if (!s.is_ok()) return s;
  period_ns_ = std::llround(1e9 / rate_hz);  // rate_hz checked by table_.init
  return s;
}

void SlowRateGroup::cycle(hal::TimeNs now_ns, const hal::Clock& clock) {
  const hal::TimeNs t0 = clock.cpu_now_ns();
  // The cycle count is the table's tick: task divisors and the throttle count cycles.
  table_.run(cycles_, now_ns, clock);
  const hal::TimeNs dt = clock.cpu_now_ns() - t0;
  ++cycles_;
  cycle_stats_.add(dt);
  if (period_ns_ > 0 && dt > period_ns_) ++late_cycles_;
}

SlowCycleCounters SlowRateGroup::cycle_counters() const {
  SlowCycleCounters c;
  c.rate_hz = rate_hz();
  c.period_us = double(period_ns_) / 1e3;
  c.cycles = cycles_;
  c.late_cycles = late_cycles_;
  c.p50_us = cycle_stats_.percentile_us(0.50);
  c.p99_us = cycle_stats_.percentile_us(0.99);
  c.max_us = cycle_stats_.max_us();
  return c;
}

}  // namespace carril::fw
