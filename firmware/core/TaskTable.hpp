#pragma once
// Rate groups inside the fixed-rate tick: each task runs on ticks where
// tick % divisor == offset, is timed, and is counted (runs, overruns of its budget, max, p99).
#include <cstdint>

#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/StaticVector.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

struct TaskSpec {
  const char* name = "";
  std::uint32_t divisor = 1;   // runs every `divisor` ticks
  std::uint32_t offset = 0;    // on ticks where tick % divisor == offset
  std::int64_t budget_ns = 0;  // compute time over this is an overrun [ns]
  void (*fn)(void* ctx) = nullptr;
  void* ctx = nullptr;

  // Binds a member function without std::function (which may allocate).
  template <auto Method, typename T>
  static TaskSpec bind(const char* name, std::uint32_t divisor, std::uint32_t offset,
                       std::int64_t budget_ns, T* obj) {
    return TaskSpec{
        name, divisor, offset, budget_ns, [](void* c) { (static_cast<T*>(c)->*Method)(); }, obj};
  }
};

// Telemetry of one task.
struct TaskCounters {
  const char* name = "";
  std::uint32_t divisor = 1, offset = 0;
  double budget_us = 0.0;
  std::uint64_t runs = 0;
  std::uint64_t overruns = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
};

class TaskTable {
 public:
  static constexpr std::size_t kMaxTasks = 12;

  // Init only. Returns false (and registers nothing) for a bad spec or a full table.
  bool add(const TaskSpec& spec);
  // Runs the tasks due on this tick, in table order.
  void run(std::uint64_t tick, const hal::Clock& clock);
  std::size_t size() const { return tasks_.size(); }
  TaskCounters counters(std::size_t i) const;

 private:
  struct Entry {
    TaskSpec spec;
    std::uint64_t runs = 0;
    std::uint64_t overruns = 0;
    LatencyStats stats;
  };
  StaticVector<Entry, kMaxTasks> tasks_;
};

}  // namespace carril::fw
