#include "firmware/core/TaskTable.hpp"

namespace carril::fw {

bool TaskTable::add(const TaskSpec& spec) {
  if (spec.fn == nullptr || spec.divisor == 0 || spec.offset >= spec.divisor || tasks_.full()) {
    return false;
  }
  Entry e;
  e.spec = spec;
  return tasks_.push_back(e);
}

void TaskTable::run(std::uint64_t tick, const hal::Clock& clock) {
  for (Entry& e : tasks_) {
    if (tick % e.spec.divisor != e.spec.offset) continue;
    const hal::TimeNs t0 = clock.cpu_now_ns();
    e.spec.fn(e.spec.ctx);
    const hal::TimeNs dt = clock.cpu_now_ns() - t0;
    ++e.runs;
    if (dt > e.spec.budget_ns) ++e.overruns;
    e.stats.add(dt);
  }
}

TaskCounters TaskTable::counters(std::size_t i) const {
  const Entry& e = tasks_[i];
  TaskCounters c;
  c.name = e.spec.name;
  c.divisor = e.spec.divisor;
  c.offset = e.spec.offset;
  c.budget_us = double(e.spec.budget_ns) / 1e3;
  c.runs = e.runs;
  c.overruns = e.overruns;
  c.p50_us = e.stats.percentile_us(0.50);
  c.p99_us = e.stats.percentile_us(0.99);
  c.max_us = e.stats.max_us();
  return c;
}

}  // namespace carril::fw
