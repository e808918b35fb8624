#pragma once
// The firmware's fixed-rate core, reduced to two jobs: run the schedule (the task table the
// target's wiring file declares) and arbitrate faults (the first one latches, is logged and
// counted, and turns every command into a quick stop). What the robot does is decided by the
// components the tasks run; they exchange messages on the data bus (Bus).
// A tick allocates nothing, blocks on nothing and makes no OS call (the clock is read only to
// time tasks).
#include <array>
#include <cstdint>
#include <span>

#include "firmware/core/Check.hpp"
#include "firmware/core/Event.hpp"
#include "firmware/core/EventLog.hpp"
#include "firmware/core/EventThrottle.hpp"
#include "firmware/core/FaultSink.hpp"
#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/TaskTable.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/MissionState.hpp"
#include "firmware/msg/SensorFrame.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

// The schedule and the fault latch, as reported.
struct ControllerTelemetry {
  std::uint64_t ticks = 0;
  std::uint64_t tick_overruns = 0;  // ticks whose compute exceeded the tick budget
  double tick_budget_us = 0.0;
  double tick_p50_us = 0.0, tick_p99_us = 0.0, tick_max_us = 0.0;
  StaticVector<TaskCounters, TaskTable::kMaxTasks> tasks;
  const char* state = "";  // the mission's state, FAULT once a fault latched
  const char* phase = "";
  MissionStatus status = MissionStatus::Starting;
  Fault fault = Fault::None;  // latched fault, if any
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts{};
  std::uint32_t checks_failed = 0;     // CARRIL_CHECKs failed in this process (CheckFailures)
  std::uint64_t events_dropped = 0;    // events overwritten before anyone read them
  std::uint64_t events_throttled = 0;  // non-fault events over kEventsPerSecond, only counted
  bool has_first_fault = false;        // first_fault holds the fault that latched
  Event first_fault;                   // kept apart from the event log: no flood removes it
};

class Controller final : public FaultSink {
 public:
  static constexpr std::size_t kEventLog = 64;
  // Non-fault events logged per second at most: a flood leaves the log room for faults.
  static constexpr std::uint32_t kEventsPerSecond = 16;
  using Events = EventLog<kEventLog>;

  // frame: published by tick() for the tasks; command: what the tasks leave for the drives.
  Controller(const hal::Clock& clock, double tick_rate_hz, Topic<SensorFrame>& frame,
             const Topic<ActuatorCommand>& command, MissionStateSource& mission);
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;

  // Init only: the next task of the target's table, in run order. An error names the task and
  // the field; nothing is registered then.
  Status add_task(const TaskSpec& spec);
  // Init only: the whole table, in run order, then check(); the first error is returned.
  Status declare(std::span<const TaskSpec> table);
  // Init only: the table is complete. An error when it is empty or the tick rate was bad.
  Status check() const;

  // One control period.
  ActuatorCommand tick(const SensorFrame& frame);

  // Init only: this many consecutive overrun ticks raise TickOverrun (a safe stop); 0, the
  // default, never does. A tick overruns when its compute exceeds the tick budget (half the
  // period) or when the loop missed its deadline (missed_deadline()).
  void set_overrun_limit(std::uint32_t ticks) { overrun_limit_ = ticks; }
  // The loop woke after the deadline of the tick about to run (it lost one or more periods).
  void missed_deadline() { missed_deadline_ = true; }

  // FaultSink: the first fault latches.
  void raise(Fault f, std::uint16_t code = 0, const char* in_state = nullptr) override;
  bool latched() const override { return fault_ != Fault::None; }

  // The mission's state name, or FAULT once a fault latched.
  const char* state_name() const;
  Fault fault() const { return fault_; }
  // The event of the fault that latched, kept apart from the log; null before any fault.
  const Event* first_fault() const { return fault_ != Fault::None ? &first_fault_ : nullptr; }
  // Fills the schedule's counters (computes percentiles: call it outside the tick or at a low
  // rate).
  void fill_telemetry(ControllerTelemetry& t) const;
  // Events since the last drain, oldest first (outside the tick).
  Events& events() { return events_; }
  double period_s() const { return period_s_; }
  std::uint64_t ticks() const { return tick_; }

 private:
  void log_phase_change(hal::TimeNs t_ns, const MissionState& now);

  const hal::Clock& clock_;
  double period_s_;
  Status init_;
  Topic<SensorFrame>& frame_;
  const Topic<ActuatorCommand>& command_;
  MissionStateSource& mission_;  // the running mission's state (the MissionRunner)
  Events events_;
  EventThrottle throttle_;  // every event goes through it into events_
  Event first_fault_;
  TaskTable tasks_;
  LatencyStats tick_stats_;
  std::int64_t tick_budget_ns_;
  std::uint64_t tick_ = 0;
  std::uint64_t tick_overruns_ = 0;
  std::uint32_t overrun_limit_ = 0;    // 0: off
  std::uint32_t overruns_in_row_ = 0;  // consecutive overrun ticks
  bool missed_deadline_ = false;       // set by the loop for the next tick
  std::uint32_t checks_seen_ = 0;      // CheckFailures::count at the last tick
  hal::TimeNs now_ns_ = 0;
  Fault fault_ = Fault::None;
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts_{};
};

}  // namespace carril::fw
