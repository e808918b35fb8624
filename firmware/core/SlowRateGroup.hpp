#pragma once
// A second task table for heavy work (planning, localisation, elevation fusion) at a low rate,
// typically 2 to 10 Hz, away from the control tick. Same TaskSpec, init/add, counters and
// throttled overrun events as TaskTable; cycle() runs one cycle of it. It holds no thread (the
// firmware makes no OS calls): the target decides what calls cycle(), e.g. a PeriodicThread on
// Linux or the simulator's lockstep loop. Not thread-safe: read counters from the thread that
// calls cycle() (hand them to others through a TripleBuffer), and give it its own EventLog.
#include <cstddef>
#include <cstdint>

#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/TaskTable.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

class EventSink;  // firmware/core/EventLog.hpp: where overrun events go

// Telemetry of the whole cycle.
struct SlowCycleCounters {
  double rate_hz = 0.0;    // [Hz]
  double period_us = 0.0;  // [us]
  std::uint64_t cycles = 0;
  std::uint64_t late_cycles = 0;  // cycles whose compute exceeded the period [cycles]
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;  // compute time of a cycle [us]
};

class SlowRateGroup {
 public:
  static constexpr std::size_t kMaxTasks = TaskTable::kMaxTasks;
  // Compute-time histogram bin [ns]: 50 us bins reach 409.6 ms, where 250 ns bins stop at 2 ms.
  static constexpr std::int64_t kStatsBinNs = 50'000;

  SlowRateGroup() : table_("slow rate group", kStatsBinNs), cycle_stats_(kStatsBinNs) {}

  // Init only; clears the group. rate_hz: how often the target calls cycle() [Hz], 1e-3 to 1e6.
  // Overrun events go to events (none when null), at most one per task per overrun_throttle_s
  // [s] of cycle time, one cycle to 3600 s.
  Status init(double rate_hz, EventSink* events = nullptr,
              double overrun_throttle_s = TaskTable::kDefaultThrottleS);
  // Init only, after init(). A task's rate_hz is at most the group's; registers nothing on error.
  Status add(const TaskSpec& spec) { return table_.add(spec); }
  // Init only: every task of a table, in order; stops at (and returns) the first error.
  Status add_all(std::span<const TaskSpec> specs) { return table_.add_all(specs); }
  // Runs one cycle: the tasks due on it, in table order; now_ns stamps overrun events [ns].
  void cycle(hal::TimeNs now_ns, const hal::Clock& clock);

  std::size_t size() const { return table_.size(); }
  TaskCounters counters(std::size_t i) const { return table_.counters(i); }
  SlowCycleCounters cycle_counters() const;
  double rate_hz() const { return table_.tick_rate_hz(); }  // [Hz]; 0 before init()
  std::uint64_t cycles() const { return cycles_; }

 private:
  TaskTable table_;
  LatencyStats cycle_stats_;
  std::int64_t period_ns_ = 0;
  std::uint64_t cycles_ = 0;
  std::uint64_t late_cycles_ = 0;
};

}  // namespace carril::fw
