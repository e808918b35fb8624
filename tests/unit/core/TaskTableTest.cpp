#include "firmware/core/TaskTable.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace carril::fw {
namespace {

// Compute time is scripted: cpu_now_ns() only moves when a task says how long it "took".
class FakeCpuClock final : public hal::Clock {
 public:
  hal::TimeNs now_ns() const override { return 0; }
  hal::TimeNs cpu_now_ns() const override {
    ++cpu_reads;
    return cpu_ns;
  }
  void sleep_until_ns(hal::TimeNs) override {}

  hal::TimeNs cpu_ns = 1'000'000;
  mutable int cpu_reads = 0;
};

// A task that records the ticks it ran on and burns a scripted amount of compute time.
struct Probe {
  FakeCpuClock* clock = nullptr;
  hal::TimeNs cost_ns = 0;
  std::uint64_t* tick = nullptr;
  std::vector<std::uint64_t> ran_on;

  static void run(void* ctx) {
    auto* p = static_cast<Probe*>(ctx);
    p->ran_on.push_back(*p->tick);
    p->clock->cpu_ns += p->cost_ns;
  }
};

void noop(void*) {}

TaskSpec spec(const char* name, std::uint32_t div, std::uint32_t off, std::int64_t budget,
              Probe* p) {
  return TaskSpec{name, div, off, budget, &Probe::run, p};
}

class TaskTableTest : public ::testing::Test {
 protected:
  Probe probe(hal::TimeNs cost) { return Probe{&clock, cost, &tick, {}}; }
  void run_ticks(std::uint64_t n) {
    for (tick = 0; tick < n; ++tick) table->run(tick, clock);
  }

  FakeCpuClock clock;
  std::uint64_t tick = 0;
  std::unique_ptr<TaskTable> table = std::make_unique<TaskTable>();  // ~400 KB: keep off stack
};

TEST_F(TaskTableTest, DivisorAndOffsetSelectTicks) {
  Probe every = probe(10);
  Probe third = probe(10);
  Probe even = probe(10);
  ASSERT_TRUE(table->add(spec("every", 1, 0, 1000, &every)));
  ASSERT_TRUE(table->add(spec("third", 3, 1, 1000, &third)));
  ASSERT_TRUE(table->add(spec("even", 2, 0, 1000, &even)));
  EXPECT_EQ(table->size(), 3U);
  run_ticks(10);
  EXPECT_EQ(every.ran_on, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(third.ran_on, (std::vector<std::uint64_t>{1, 4, 7}));
  EXPECT_EQ(even.ran_on, (std::vector<std::uint64_t>{0, 2, 4, 6, 8}));
  EXPECT_EQ(table->counters(0).runs, 10U);
  EXPECT_EQ(table->counters(1).runs, 3U);
  EXPECT_EQ(table->counters(2).runs, 5U);
  // Two clock reads per run, none for tasks not due.
  EXPECT_EQ(clock.cpu_reads, 2 * (10 + 3 + 5));
}

TEST_F(TaskTableTest, TasksRunInTableOrder) {
  std::vector<int> order;
  struct Tag {
    std::vector<int>* order;
    int id;
    static void run(void* c) {
      auto* t = static_cast<Tag*>(c);
      t->order->push_back(t->id);
    }
  };
  Tag a{&order, 1}, b{&order, 2}, c{&order, 3};
  ASSERT_TRUE(table->add(TaskSpec{"a", 1, 0, 0, &Tag::run, &a}));
  ASSERT_TRUE(table->add(TaskSpec{"b", 2, 1, 0, &Tag::run, &b}));
  ASSERT_TRUE(table->add(TaskSpec{"c", 1, 0, 0, &Tag::run, &c}));
  table->run(0, clock);
  table->run(1, clock);
  EXPECT_EQ(order, (std::vector<int>{1, 3, 1, 2, 3}));
}

TEST_F(TaskTableTest, OverrunCountedOnlyOverBudget) {
  Probe slow = probe(1500);   // 1.5 us against a 1 us budget
  Probe fast = probe(400);    // 0.4 us against a 1 us budget
  Probe exact = probe(1000);  // exactly at budget: not an overrun
  ASSERT_TRUE(table->add(spec("slow", 1, 0, 1000, &slow)));
  ASSERT_TRUE(table->add(spec("fast", 1, 0, 1000, &fast)));
  ASSERT_TRUE(table->add(spec("exact", 1, 0, 1000, &exact)));
  run_ticks(4);
  const TaskCounters s = table->counters(0);
  EXPECT_EQ(s.runs, 4U);
  EXPECT_EQ(s.overruns, 4U);
  EXPECT_DOUBLE_EQ(s.max_us, 1.5);
  EXPECT_DOUBLE_EQ(s.budget_us, 1.0);
  const TaskCounters f = table->counters(1);
  EXPECT_EQ(f.runs, 4U);
  EXPECT_EQ(f.overruns, 0U);
  EXPECT_DOUBLE_EQ(f.max_us, 0.4);
  EXPECT_EQ(table->counters(2).overruns, 0U);
}

TEST_F(TaskTableTest, OverrunsOnlyOnSlowRuns) {
  Probe p = probe(0);
  ASSERT_TRUE(table->add(spec("varying", 1, 0, 50'000, &p)));
  // Costs 10, 60, 20, 80 us: two over the 50 us budget.
  const hal::TimeNs costs[] = {10'000, 60'000, 20'000, 80'000};
  for (std::uint64_t t = 0; t < 4; ++t) {
    tick = t;
    p.cost_ns = costs[t];
    table->run(t, clock);
  }
  const TaskCounters c = table->counters(0);
  EXPECT_EQ(c.runs, 4U);
  EXPECT_EQ(c.overruns, 2U);
  EXPECT_DOUBLE_EQ(c.max_us, 80.0);
  // Nearest rank over {10, 20, 60, 80}: p50 is the 2nd (20 us), p99 the 4th (80 us).
  EXPECT_GE(c.p50_us, 20.0);
  EXPECT_LE(c.p50_us, 20.25);
  EXPECT_DOUBLE_EQ(c.p99_us, 80.0);
}

TEST_F(TaskTableTest, CountersReportSpec) {
  Probe p = probe(0);
  ASSERT_TRUE(table->add(spec("estimator", 5, 3, 250'000, &p)));
  const TaskCounters c = table->counters(0);
  EXPECT_STREQ(c.name, "estimator");
  EXPECT_EQ(c.divisor, 5U);
  EXPECT_EQ(c.offset, 3U);
  EXPECT_DOUBLE_EQ(c.budget_us, 250.0);
  EXPECT_EQ(c.runs, 0U);
  EXPECT_EQ(c.overruns, 0U);
  EXPECT_EQ(c.max_us, 0.0);
}

TEST_F(TaskTableTest, AddRejectsBadSpecs) {
  int dummy = 0;
  EXPECT_FALSE(table->add(TaskSpec{"div0", 0, 0, 1000, &noop, &dummy}));
  EXPECT_FALSE(table->add(TaskSpec{"off=div", 3, 3, 1000, &noop, &dummy}));
  EXPECT_FALSE(table->add(TaskSpec{"off>div", 2, 5, 1000, &noop, &dummy}));
  EXPECT_FALSE(table->add(TaskSpec{"nullfn", 1, 0, 1000, nullptr, &dummy}));
  EXPECT_EQ(table->size(), 0U);
  // The largest valid offset is accepted; a null ctx is fine.
  EXPECT_TRUE(table->add(TaskSpec{"ok", 3, 2, 1000, &noop, nullptr}));
  EXPECT_EQ(table->size(), 1U);
}

TEST_F(TaskTableTest, AddRejectsThirteenthTask) {
  static_assert(TaskTable::kMaxTasks == 12);
  for (std::size_t i = 0; i < TaskTable::kMaxTasks; ++i) {
    EXPECT_TRUE(table->add(TaskSpec{"t", 1, 0, 1000, &noop, nullptr})) << i;
  }
  EXPECT_EQ(table->size(), 12U);
  EXPECT_FALSE(table->add(TaskSpec{"13th", 1, 0, 1000, &noop, nullptr}));
  EXPECT_EQ(table->size(), 12U);
}

struct Counter {
  int calls = 0;
  void tick() { ++calls; }
};

TEST_F(TaskTableTest, BindCallsMemberFunction) {
  Counter a, b;
  ASSERT_TRUE(table->add(TaskSpec::bind<&Counter::tick>("a", 1, 0, 1000, &a)));
  ASSERT_TRUE(table->add(TaskSpec::bind<&Counter::tick>("b", 2, 1, 1000, &b)));
  const TaskSpec s = TaskSpec::bind<&Counter::tick>("direct", 4, 2, 7, &a);
  EXPECT_STREQ(s.name, "direct");
  EXPECT_EQ(s.divisor, 4U);
  EXPECT_EQ(s.offset, 2U);
  EXPECT_EQ(s.budget_ns, 7);
  EXPECT_EQ(s.ctx, &a);
  run_ticks(6);
  EXPECT_EQ(a.calls, 6);
  EXPECT_EQ(b.calls, 3);  // ticks 1, 3, 5
  s.fn(s.ctx);
  EXPECT_EQ(a.calls, 7);
}

}  // namespace
}  // namespace carril::fw
