#include "firmware/core/SlowRateGroup.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "firmware/core/EventLog.hpp"

namespace carril::fw {
namespace {

// Compute time is scripted: cpu_now_ns() only moves when a task says how long it "took".
class FakeCpuClock final : public hal::Clock {
 public:
  hal::TimeNs now_ns() const override { return 0; }
  hal::TimeNs cpu_now_ns() const override { return cpu_ns; }
  void sleep_until_ns(hal::TimeNs) override {}
  hal::TimeNs cpu_ns = 0;
};

struct Work {
  FakeCpuClock* clock = nullptr;
  hal::TimeNs cost_ns = 0;
  int runs = 0;
  void step() {
    ++runs;
    clock->cpu_ns += cost_ns;
  }
};

constexpr double kRateHz = 5.0;
constexpr hal::TimeNs kPeriodNs = 200'000'000;  // at kRateHz
constexpr std::int64_t kMs = 1'000'000;         // [ns]

class SlowRateGroupTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(group->init(kRateHz, &log).is_ok()); }
  void cycles(int n) {
    for (int i = 0; i < n; ++i) {
      group->cycle(hal::TimeNs(group->cycles()) * kPeriodNs, clock);
    }
  }
  TaskSpec task(const char* name, double rate_hz, std::int64_t budget_ns, Work* w,
                Severity severity = Severity::Warning) {
    return TaskSpec::bind<&Work::step>(name, rate_hz, 0, budget_ns, w, severity);
  }

  FakeCpuClock clock;
  EventLog<16> log;
  std::unique_ptr<SlowRateGroup> group = std::make_unique<SlowRateGroup>();  // ~430 KB
};

TEST_F(SlowRateGroupTest, TasksRunAtTheirRateWithinTheGroup) {
  Work planner{&clock, 1 * kMs};
  Work mapper{&clock, 1 * kMs};
  ASSERT_TRUE(group->add(task("planner", 5.0, 50 * kMs, &planner)).is_ok());
  ASSERT_TRUE(group->add(task("mapper", 1.0, 50 * kMs, &mapper)).is_ok());  // every 5th cycle
  EXPECT_EQ(group->size(), 2U);
  EXPECT_EQ(group->counters(1).divisor, 5U);
  cycles(10);
  EXPECT_EQ(planner.runs, 10);
  EXPECT_EQ(mapper.runs, 2);
  EXPECT_EQ(group->cycles(), 10U);
  EXPECT_EQ(group->counters(0).runs, 10U);
  EXPECT_EQ(group->counters(1).runs, 2U);
}

TEST_F(SlowRateGroupTest, InitErrorsNameTheGroupAndTheField) {
  const Status s = group->init(0.0);
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("slow rate group: tick_rate_hz: 0 Hz"), std::string::npos)
      << s.message();
  EXPECT_DOUBLE_EQ(group->rate_hz(), 0.0);
  ASSERT_TRUE(group->init(kRateHz).is_ok());
  Work w{&clock, 0};
  // Faster than the group runs cannot be scheduled.
  const Status fast = group->add(task("localiser", 10.0, kMs, &w));
  ASSERT_FALSE(fast.is_ok());
  const std::string m = fast.message();
  EXPECT_NE(m.find("slow rate group: task 'localiser': rate_hz: 10 Hz"), std::string::npos) << m;
  EXPECT_NE(m.find("5 Hz"), std::string::npos) << m;
  EXPECT_EQ(group->size(), 0U);
}

// At 5 Hz, 1 s is 5 cycles: a task overrunning every cycle gives events on cycles 0, 5 and 10,
// the later ones each standing for the 5 overruns since the one before.
TEST_F(SlowRateGroupTest, OverrunEventsThrottledInCycles) {
  Work fusion{&clock, 80 * kMs};
  ASSERT_TRUE(group->add(task("fusion", 5.0, 50 * kMs, &fusion, Severity::Error)).is_ok());
  cycles(12);
  std::vector<Event> ev;
  Event e;
  while (log.pop(e)) ev.push_back(e);
  ASSERT_EQ(ev.size(), 3U);
  EXPECT_EQ(ev[0].count, 1U);
  EXPECT_EQ(ev[0].t_ns, 0);
  EXPECT_EQ(ev[1].count, 5U);
  EXPECT_EQ(ev[1].t_ns, 5 * kPeriodNs);
  EXPECT_EQ(ev[2].count, 5U);
  EXPECT_EQ(ev[2].t_ns, 10 * kPeriodNs);
  for (const Event& x : ev) {
    EXPECT_EQ(x.kind, EventKind::Overrun);
    EXPECT_EQ(x.severity, Severity::Error);
    EXPECT_STREQ(x.task, "fusion");
    EXPECT_DOUBLE_EQ(x.took_us, 80'000.0);
    EXPECT_DOUBLE_EQ(x.budget_us, 50'000.0);
  }
  EXPECT_EQ(group->counters(0).overruns, 12U);
  EXPECT_EQ(group->counters(0).overrun_events, 3U);
}

TEST_F(SlowRateGroupTest, CycleCountersAndPercentilesOfSlowWork) {
  Work a{&clock, 30 * kMs};
  Work b{&clock, 20 * kMs};
  ASSERT_TRUE(group->add(task("a", 5.0, 100 * kMs, &a)).is_ok());
  ASSERT_TRUE(group->add(task("b", 5.0, 100 * kMs, &b)).is_ok());
  cycles(4);
  b.cost_ns = 190 * kMs;  // 220 ms of a 200 ms period: late
  cycles(1);
  const SlowCycleCounters c = group->cycle_counters();
  EXPECT_DOUBLE_EQ(c.rate_hz, 5.0);
  EXPECT_DOUBLE_EQ(c.period_us, 200'000.0);
  EXPECT_EQ(c.cycles, 5U);
  EXPECT_EQ(c.late_cycles, 1U);
  EXPECT_DOUBLE_EQ(c.max_us, 220'000.0);
  // 50 ms cycles are inside the wide-binned histogram: p50 within one 50 us bin, not the max.
  EXPECT_GE(c.p50_us, 50'000.0);
  EXPECT_LE(c.p50_us, 50'050.0);
  const TaskCounters ta = group->counters(0);
  EXPECT_GE(ta.p99_us, 30'000.0);
  EXPECT_LE(ta.p99_us, 30'050.0);
}

TEST_F(SlowRateGroupTest, InitStartsAfresh) {
  Work w{&clock, 300 * kMs};
  ASSERT_TRUE(group->add(task("w", 5.0, kMs, &w)).is_ok());
  cycles(3);
  ASSERT_TRUE(group->init(2.0).is_ok());
  EXPECT_EQ(group->size(), 0U);
  EXPECT_EQ(group->cycles(), 0U);
  const SlowCycleCounters c = group->cycle_counters();
  EXPECT_EQ(c.cycles, 0U);
  EXPECT_EQ(c.late_cycles, 0U);
  EXPECT_EQ(c.max_us, 0.0);
  EXPECT_DOUBLE_EQ(c.period_us, 500'000.0);
}

}  // namespace
}  // namespace carril::fw
