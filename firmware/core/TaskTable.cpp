#include "firmware/core/TaskTable.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "firmware/core/Event.hpp"
#include "firmware/core/EventLog.hpp"

namespace carril::fw {

namespace {
constexpr double kMaxDivisor = 4294967295.0;  // the largest std::uint32_t
}  // namespace

std::uint32_t TaskTable::divisor_for(double tick_rate_hz, double rate_hz) {
  // Guards first, so no input divides by zero, overflows or compares NaN (all trap in tests).
  if (!std::isfinite(tick_rate_hz) || !std::isfinite(rate_hz) || rate_hz <= 0.0 ||
      tick_rate_hz <= rate_hz) {
    return 1;
  }
  if (rate_hz < tick_rate_hz / kMaxDivisor) return std::uint32_t(kMaxDivisor);
  // The 1e-9 keeps an exact ratio (100 Hz / 20 Hz) from flooring to one less through rounding.
  const double d = std::floor(tick_rate_hz / rate_hz + 1e-9);
  return static_cast<std::uint32_t>(d < kMaxDivisor ? d : kMaxDivisor);
}

Status TaskTable::init(double tick_rate_hz, EventSink* events, double overrun_throttle_s) {
  tasks_.clear();
  tick_rate_hz_ = 0.0;
  events_ = nullptr;
  throttle_ticks_ = 1;
  // isfinite first: an ordered compare on NaN raises FE_INVALID, which the tests trap.
  if (!std::isfinite(tick_rate_hz) || tick_rate_hz < kMinTickRateHz ||
      tick_rate_hz > kMaxTickRateHz) {
    return Status::error("%s: tick_rate_hz: %g Hz, expected %g to %g Hz", label_, tick_rate_hz,
                         kMinTickRateHz, kMaxTickRateHz);
  }
  const double min_throttle_s = 1.0 / tick_rate_hz;
  if (!std::isfinite(overrun_throttle_s) || overrun_throttle_s < min_throttle_s * (1.0 - 1e-9) ||
      overrun_throttle_s > kMaxThrottleS) {
    return Status::error("%s: overrun_throttle_s: %g s, expected %g (one tick) to %g s", label_,
                         overrun_throttle_s, min_throttle_s, kMaxThrottleS);
  }
  if (stats_bin_ns_ <= 0) {
    return Status::error("%s: stats_bin_ns: %lld ns, expected above 0 ns", label_,
                         static_cast<long long>(stats_bin_ns_));
  }
  const double ticks = std::floor(overrun_throttle_s * tick_rate_hz + 1e-9);
  throttle_ticks_ = ticks >= 1.0 ? static_cast<std::uint64_t>(ticks) : 1;
  tick_rate_hz_ = tick_rate_hz;
  events_ = events;
  return Status::ok();
}

Status TaskTable::add(const TaskSpec& spec) {
  if (spec.name == nullptr || spec.name[0] == '\0') {
    return Status::error("%s: task #%zu: name: empty, expected a non-empty static string", label_,
                         tasks_.size());
  }
  const char* name = spec.name;
  if (tick_rate_hz_ <= 0.0) {
    return Status::error("%s: task '%s': table not initialised, expected init(tick_rate_hz) first",
                         label_, name);
  }
  if (tasks_.full()) {
    return Status::error("%s: task '%s': table full, capacity %zu tasks", label_, name, kMaxTasks);
  }
  for (std::size_t i = 0; i < tasks_.size(); ++i) {
    if (std::strcmp(tasks_[i].spec.name, name) == 0) {
      return Status::error("%s: task '%s': name: already used by task #%zu, expected unique names",
                           label_, name, i);
    }
  }
  const double r = spec.rate_hz;
  const double min_rate = tick_rate_hz_ / kMaxDivisor;  // slower would overflow the divisor
  if (!std::isfinite(r) || r <= 0.0 || r < min_rate || r > tick_rate_hz_) {
    return Status::error("%s: task '%s': rate_hz: %g Hz, expected %g to %g Hz (the tick rate)",
                         label_, name, r, min_rate, tick_rate_hz_);
  }
  const std::uint32_t divisor = divisor_for(tick_rate_hz_, r);
  if (spec.offset >= divisor) {
    return Status::error(
        "%s: task '%s': offset: %u ticks, expected 0 to %u ticks (divisor %u: %g Hz of a %g Hz "
        "tick)",
        label_, name, spec.offset, divisor - 1, divisor, r, tick_rate_hz_);
  }
  if (spec.budget_ns <= 0) {
    return Status::error("%s: task '%s': budget_ns: %lld ns, expected above 0 ns", label_, name,
                         static_cast<long long>(spec.budget_ns));
  }
  if (spec.fn == nullptr) {
    return Status::error("%s: task '%s': fn: null, expected a function", label_, name);
  }
  Entry e;
  e.spec = spec;
  e.divisor = divisor;
  e.stats = LatencyStats(stats_bin_ns_);
  tasks_.push_back(e);
  return Status::ok();
}

void TaskTable::run(std::uint64_t tick, hal::TimeNs now_ns, const hal::Clock& clock) {
  // One clock read per task run, plus one: a task's time ends where the next one's begins. A
  // read is a system call where the clock has no vDSO (user-mode-linux: about 75 us).
  hal::TimeNs t_prev = 0;
  bool timed = false;  // t_prev holds the end of the last task run
  for (Entry& e : tasks_) {
    if (tick % e.divisor == e.spec.offset) {
      if (!timed) t_prev = clock.cpu_now_ns();
      timed = true;
      e.spec.fn(e.spec.ctx);
      const hal::TimeNs t = clock.cpu_now_ns();
      const hal::TimeNs dt = t - t_prev;
      t_prev = t;
      ++e.runs;
      e.stats.add(dt);
      if (dt > e.spec.budget_ns) {
        ++e.overruns;
        if (e.unreported < UINT32_MAX) ++e.unreported;  // saturates: Event::count is 32 bits
        if (dt > e.unreported_max_ns) e.unreported_max_ns = dt;
      }
    }
    // Checked on every tick, not only when the task runs, so the overruns held back by the
    // throttle are reported once the interval is over even if the task stops overrunning.
    if (e.unreported > 0 && (!e.reported || tick - e.last_report_tick >= throttle_ticks_)) {
      report(e, tick, now_ns);
      timed = false;  // the report's time is no task's
    }
  }
}

void TaskTable::report(Entry& e, std::uint64_t tick, hal::TimeNs now_ns) {
  if (events_ != nullptr) {
    Event ev;
    ev.t_ns = now_ns;
    ev.kind = EventKind::Overrun;
    ev.severity = e.spec.overrun_severity;
    ev.task = e.spec.name;
    ev.count = e.unreported;
    ev.took_us = double(e.unreported_max_ns) / 1e3;
    ev.budget_us = double(e.spec.budget_ns) / 1e3;
    events_->push(ev);
    ++e.overrun_events;
  }
  e.unreported = 0;
  e.unreported_max_ns = 0;
  e.reported = true;
  e.last_report_tick = tick;
}

TaskCounters TaskTable::counters(std::size_t i) const {
  const Entry& e = tasks_[i];
  TaskCounters c;
  c.name = e.spec.name;
  c.rate_hz = e.spec.rate_hz;
  c.divisor = e.divisor;
  c.offset = e.spec.offset;
  c.budget_us = double(e.spec.budget_ns) / 1e3;
  c.runs = e.runs;
  c.overruns = e.overruns;
  c.overrun_events = e.overrun_events;
  c.p50_us = e.stats.percentile_us(0.50);
  c.p99_us = e.stats.percentile_us(0.99);
  c.max_us = e.stats.max_us();
  return c;
}

}  // namespace carril::fw
