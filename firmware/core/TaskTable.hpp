#pragma once
// Rate groups inside the fixed-rate tick. Tasks are declared by rate (the target derives the
// rates from its configured sensor rates); the table turns each into a divisor of the tick, runs
// the task on ticks where tick % divisor == offset, times it, counts it (runs, overruns of its
// budget, p50/p99/max) and reports overruns as throttled events: at most one per task per
// throttle interval, carrying how many overruns it stands for (F Prime's rate group cycle slip).
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "firmware/core/Event.hpp"
#include "firmware/core/EventLog.hpp"
#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/Severity.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

class EventSink;  // firmware/core/EventLog.hpp: where overrun events go

struct TaskSpec {
  const char* name = "";       // unique in its table; a static string (kept, not copied)
  double rate_hz = 0.0;        // how often it should run [Hz], at most the tick rate
  std::uint32_t offset = 0;    // tick within its period it runs on [ticks], 0 to divisor - 1
  std::int64_t budget_ns = 0;  // compute time over this is an overrun [ns], > 0
  Severity overrun_severity = Severity::Warning;  // severity of its overrun events
  void (*fn)(void* ctx) = nullptr;
  void* ctx = nullptr;

  // Binds a member function without std::function (which may allocate).
  template <auto Method, typename T>
  static TaskSpec bind(const char* name, double rate_hz, std::uint32_t offset,
                       std::int64_t budget_ns, T* obj,
                       Severity overrun_severity = Severity::Warning) {
    return TaskSpec{name,      rate_hz,          offset,
                    budget_ns, overrun_severity, [](void* c) { (static_cast<T*>(c)->*Method)(); },
                    obj};
  }
  // An integer rate does not compile: it is most likely a divisor from before tasks were
  // declared by rate (bind("health", 1, ...) would run at 1 Hz). Write 100.0, or pass a double.
  template <auto Method, typename T, typename R>
  requires std::is_integral_v<R>
  static TaskSpec bind(const char* name, R rate_hz, std::uint32_t offset, std::int64_t budget_ns,
                       T* obj, Severity overrun_severity = Severity::Warning) = delete;
};

// Telemetry of one task.
struct TaskCounters {
  const char* name = "";
  double rate_hz = 0.0;                   // declared rate [Hz]
  std::uint32_t divisor = 1, offset = 0;  // runs on ticks where tick % divisor == offset
  double budget_us = 0.0;                 // [us]
  std::uint64_t runs = 0;
  std::uint64_t overruns = 0;        // runs over budget, each counted (not throttled)
  std::uint64_t overrun_events = 0;  // events reported for them (throttled)
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;  // compute time [us]
};

class TaskTable {
 public:
  static constexpr std::size_t kMaxTasks = 12;
  static constexpr double kMinTickRateHz = 1e-3;    // [Hz]; bounds keep the arithmetic finite
  static constexpr double kMaxTickRateHz = 1e6;     // [Hz]
  static constexpr double kMaxThrottleS = 3600.0;   // [s]
  static constexpr double kDefaultThrottleS = 1.0;  // [s]

  // label names the table in error messages; stats_bin_ns is the compute-time histogram's bin
  // width [ns] (LatencyStats covers 8192 bins: 250 ns bins reach 2 ms).
  explicit TaskTable(const char* label = "task table", std::int64_t stats_bin_ns = 250)
      : label_(label), stats_bin_ns_(stats_bin_ns) {}

  // Init only; clears the table. tick_rate_hz: how often run() is called [Hz], 1e-3 to 1e6.
  // Overrun events go to events (none when null), at most one per task per overrun_throttle_s of
  // tick time [s], one tick to 3600 s.
  Status init(double tick_rate_hz, EventSink* events = nullptr,
              double overrun_throttle_s = kDefaultThrottleS);
  // Init only, after init(). Registers nothing on error.
  Status add(const TaskSpec& spec);
  // Init only: every task of a table, in order; stops at (and returns) the first error.
  Status add_all(std::span<const TaskSpec> specs) {
    for (const TaskSpec& s : specs) {
      if (Status st = add(s); !st) return st;
    }
    return Status::ok();
  }
  // Runs the tasks due on this tick, in table order; now_ns stamps overrun events [ns].
  void run(std::uint64_t tick, hal::TimeNs now_ns, const hal::Clock& clock);

  std::size_t size() const { return tasks_.size(); }
  TaskCounters counters(std::size_t i) const;
  double tick_rate_hz() const { return tick_rate_hz_; }  // [Hz]; 0 before init()
  // The throttle interval: overrun events of one task are at least this far apart [ticks].
  std::uint64_t throttle_ticks() const { return throttle_ticks_; }
  // The divisor of a task at rate_hz: max(1, floor(tick_rate_hz / rate_hz + 1e-9)) [ticks].
  // Valid for rates add() accepts.
  static std::uint32_t divisor_for(double tick_rate_hz, double rate_hz);

 private:
  struct Entry {
    TaskSpec spec;
    std::uint32_t divisor = 1;
    std::uint64_t runs = 0;
    std::uint64_t overruns = 0;
    std::uint64_t overrun_events = 0;
    std::uint32_t unreported = 0;        // overruns since the last event
    std::int64_t unreported_max_ns = 0;  // the longest of them [ns]
    bool reported = false;               // an event was ever reported
    std::uint64_t last_report_tick = 0;
    LatencyStats stats;
  };
  void report(Entry& e, std::uint64_t tick, hal::TimeNs now_ns);

  const char* label_;
  std::int64_t stats_bin_ns_;
  double tick_rate_hz_ = 0.0;
  EventSink* events_ = nullptr;
  std::uint64_t throttle_ticks_ = 1;
  StaticVector<Entry, kMaxTasks> tasks_;
};

}  // namespace carril::fw
