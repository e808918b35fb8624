#pragma once
// Runs a function periodically on its own POSIX thread, for a rate group the target moves off
// the control loop's thread (e.g. a SlowRateGroup). Absolute deadlines on CLOCK_MONOTONIC
// (next += period; clock_nanosleep TIMER_ABSTIME), so jitter does not accumulate into drift; a
// cycle that ends after its next deadline has the missed periods counted and skipped, never
// bursted (as FixedRateLoop). SCHED_FIFO when permitted; without the privilege it runs
// SCHED_OTHER and says so (note()) instead of failing, so it also runs on a developer's laptop.
#include <pthread.h>

#include <atomic>
#include <cstdint>

#include "hal/Types.hpp"

namespace carril::hal {

class PeriodicThread {
 public:
  enum class Policy : std::uint8_t { None, Fifo, Other };  // None: not started

  PeriodicThread() = default;
  ~PeriodicThread() { stop(); }
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;

  // Calls fn(ctx) every period_ns [ns] (> 0) on a new thread named name (first 15 characters),
  // the first call at once. priority: SCHED_FIFO priority (1 to 99), or 0 for SCHED_OTHER. Falls
  // back to SCHED_OTHER when SCHED_FIFO is not permitted (policy(), note()). Returns false, and
  // starts nothing, for bad arguments, a thread already running or a failed pthread_create
  // (reason in note()).
  bool start(const char* name, TimeNs period_ns, int priority, void (*fn)(void* ctx), void* ctx);
  // Lets the current cycle finish and joins the thread: returns within about one period plus one
  // cycle. No-op when not running.
  void stop();

  bool running() const { return running_; }
  // The scheduling policy the thread got (None before start()).
  Policy policy() const { return policy_; }
  // Why start() failed or fell back to SCHED_OTHER; "" when it got what it asked for.
  const char* note() const { return note_; }
  // Calls of fn since start() [cycles]; readable from any thread.
  std::uint64_t cycles() const { return cycles_.load(std::memory_order_relaxed); }
  // Periods skipped because a cycle ended after its next deadline [periods]; any thread.
  std::uint64_t missed_deadlines() const { return missed_.load(std::memory_order_relaxed); }

 private:
  static void* entry(void* self);
  void loop();

  void (*fn_)(void*) = nullptr;
  void* ctx_ = nullptr;
  TimeNs period_ns_ = 0;
  pthread_t thread_{};
  bool running_ = false;
  Policy policy_ = Policy::None;
  char name_[16] = {};  // Linux thread names hold 15 characters and the terminator
  char note_[160] = {};
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> cycles_{0};
  std::atomic<std::uint64_t> missed_{0};
};

}  // namespace carril::hal
