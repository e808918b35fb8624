#include "firmware/app/Controller.hpp"

#include <cmath>

namespace carril::fw {

namespace {
// A usable tick rate; quiet comparisons, so a NaN is refused without a floating-point trap.
bool usable_rate(double hz) {
  return std::isfinite(hz) && std::isgreater(hz, 0.0);
}
}  // namespace

Controller::Controller(const hal::Clock& clock, double tick_rate_hz, Topic<SensorFrame>& frame,
                       const Topic<ActuatorCommand>& command, MissionStateSource& mission)
    : clock_(clock),
      period_s_(usable_rate(tick_rate_hz) ? 1.0 / tick_rate_hz : 0.0),
      frame_(frame),
      command_(command),
      mission_(mission),
      throttle_(events_, kEventsPerSecond, 1'000'000'000),
      tasks_("controller tasks"),
      tick_budget_ns_(usable_rate(tick_rate_hz) ? static_cast<std::int64_t>(0.5e9 / tick_rate_hz)
                                                : 0) {
  init_ = tasks_.init(tick_rate_hz, &throttle_);
  // Checks that failed before this controller existed belong to someone else (another test).
  checks_seen_ = check_failures().count;
}

Status Controller::add_task(const TaskSpec& spec) {
  if (!init_) return init_;
  return tasks_.add(spec);
}

Status Controller::declare(std::span<const TaskSpec> table) {
  if (!init_) return init_;
  if (Status s = tasks_.add_all(table); !s) return s;
  return check();
}

Status Controller::check() const {
  if (!init_) return init_;
  if (tasks_.size() == 0) return Status::error("controller tasks: no task declared");
  return Status::ok();
}

const char* Controller::state_name() const {
  return fault_ != Fault::None ? "FAULT" : mission_.state().name;
}

ActuatorCommand Controller::tick(const SensorFrame& frame) {
  const hal::TimeNs t0 = clock_.cpu_now_ns();
  now_ns_ = frame.now_ns;
  frame_.publish(frame, frame.now_ns);
  const bool faulted_before = latched();
  const MissionState before = mission_.state();
  tasks_.run(tick_, frame.now_ns, clock_);
  const MissionState after = mission_.state();
  log_phase_change(frame.now_ns, after);
  if (latched() != faulted_before || after.id != before.id) {
    Event e;
    e.t_ns = frame.now_ns;
    e.kind = EventKind::StateChange;
    e.from = faulted_before ? "FAULT" : before.name;
    e.to = latched() ? "FAULT" : after.name;
    throttle_.push(e);
  }
  // A check failed anywhere (in a task, or in another thread of this process): a programming
  // error, and the robot stops.
  if (const CheckFailures c = check_failures(); c.count != checks_seen_) {
    checks_seen_ = c.count;
    raise(Fault::CheckFailed, static_cast<std::uint16_t>(c.line));
  }
  ++tick_;
  const hal::TimeNs dt = clock_.cpu_now_ns() - t0;
  tick_stats_.add(dt);
  if (dt > tick_budget_ns_) ++tick_overruns_;
  const bool overran = dt > tick_budget_ns_ || missed_deadline_;
  missed_deadline_ = false;
  overruns_in_row_ = overran ? overruns_in_row_ + 1 : 0;
  if (overrun_limit_ > 0 && overruns_in_row_ >= overrun_limit_) {
    raise(Fault::TickOverrun, static_cast<std::uint16_t>(overrun_limit_));
  }
  ActuatorCommand cmd = command_.get();
  if (latched()) {
    // The latch has the last word, whatever a task left behind.
    quick_stop(cmd);
  }
  return cmd;
}

void Controller::log_phase_change(hal::TimeNs t_ns, const MissionState& now) {
  if (const char* phase = mission_.take_phase_change()) {
    Event e;
    e.t_ns = t_ns;
    e.kind = EventKind::Phase;
    e.from = e.to = now.name;
    e.phase = phase;
    throttle_.push(e);
  }
}

void Controller::raise(Fault f, std::uint16_t code, const char* in_state) {
  if (fault_ != Fault::None) return;  // the first fault is the one reported
  const char* was = in_state != nullptr ? in_state : mission_.state().name;
  fault_ = f;
  ++fault_counts_[std::size_t(f)];
  Event e;
  e.t_ns = now_ns_;
  e.kind = EventKind::Fault;
  e.severity = Severity::Error;
  e.from = was;
  e.to = "FAULT";
  e.fault = f;
  e.code = code;
  first_fault_ = e;
  throttle_.push(e);
}

void Controller::fill_telemetry(ControllerTelemetry& t) const {
  t.ticks = tick_;
  t.tick_overruns = tick_overruns_;
  t.tick_budget_us = double(tick_budget_ns_) / 1e3;
  t.tick_p50_us = tick_stats_.percentile_us(0.50);
  t.tick_p99_us = tick_stats_.percentile_us(0.99);
  t.tick_max_us = tick_stats_.max_us();
  t.tasks.clear();
  for (std::size_t i = 0; i < tasks_.size(); ++i) t.tasks.push_back(tasks_.counters(i));
  const MissionState ms = mission_.state();
  t.state = state_name();
  t.phase = ms.phase;
  t.status = fault_ != Fault::None ? MissionStatus::Failed : ms.status;
  t.fault = fault_;
  t.fault_counts = fault_counts_;
  t.checks_failed = check_failures().count;
  t.events_dropped = events_.dropped();
  t.events_throttled = throttle_.throttled();
  t.has_first_fault = fault_ != Fault::None;
  t.first_fault = first_fault_;
}

}  // namespace carril::fw
