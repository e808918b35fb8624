#include "firmware/core/TaskTable.hpp"

#include <gtest/gtest.h>

#include <limits>
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

TaskSpec spec(const char* name, double rate_hz, std::uint32_t off, std::int64_t budget, Probe* p,
              Severity severity = Severity::Warning) {
  return TaskSpec{name, rate_hz, off, budget, severity, &Probe::run, p};
}

TaskSpec plain(const char* name, double rate_hz = 100.0, std::uint32_t off = 0,
               std::int64_t budget = 1000) {
  return TaskSpec{name, rate_hz, off, budget, Severity::Warning, &noop, nullptr};
}

constexpr double kTickHz = 100.0;
constexpr hal::TimeNs kTickNs = 10'000'000;  // at kTickHz

class TaskTableTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(table->init(kTickHz, &log).is_ok()); }
  Probe probe(hal::TimeNs cost) { return Probe{&clock, cost, &tick, {}}; }
  void run_tick(std::uint64_t t) {
    tick = t;
    table->run(t, hal::TimeNs(t) * kTickNs, clock);
  }
  void run_ticks(std::uint64_t from, std::uint64_t to) {
    for (std::uint64_t t = from; t < to; ++t) run_tick(t);
  }
  std::vector<Event> drain() {
    std::vector<Event> out;
    Event e;
    while (log.pop(e)) out.push_back(e);
    return out;
  }

  FakeCpuClock clock;
  std::uint64_t tick = 0;
  EventLog<64> log;
  std::unique_ptr<TaskTable> table = std::make_unique<TaskTable>();  // ~400 KB: keep off stack
};

// --- schedule -------------------------------------------------------------------------------

TEST_F(TaskTableTest, RateAndOffsetSelectTicks) {
  Probe every = probe(10);
  Probe third = probe(10);
  Probe even = probe(10);
  ASSERT_TRUE(table->add(spec("every", 100.0, 0, 1000, &every)).is_ok());
  ASSERT_TRUE(table->add(spec("third", 100.0 / 3.0, 1, 1000, &third)).is_ok());
  ASSERT_TRUE(table->add(spec("even", 50.0, 0, 1000, &even)).is_ok());
  EXPECT_EQ(table->size(), 3U);
  run_ticks(0, 10);
  EXPECT_EQ(every.ran_on, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(third.ran_on, (std::vector<std::uint64_t>{1, 4, 7}));
  EXPECT_EQ(even.ran_on, (std::vector<std::uint64_t>{0, 2, 4, 6, 8}));
  EXPECT_EQ(table->counters(0).runs, 10U);
  EXPECT_EQ(table->counters(1).runs, 3U);
  EXPECT_EQ(table->counters(2).runs, 5U);
  // One clock read per run plus one per tick that ran a task (a task's time ends where the next
  // one's begins), none for tasks not due: each read may be a system call.
  EXPECT_EQ(clock.cpu_reads, (10 + 3 + 5) + 10);
}

// The rule reproduces the schedule the Controller had: camera 30 Hz -> every 3 ticks, lidar
// 20 Hz -> 5, telemetry 10 Hz -> 10 at 100 Hz; at 50 Hz, 30 Hz runs every tick and 20 Hz every 2.
TEST(TaskTableDivisorTest, DivisorsFromRates) {
  struct Case {
    double tick_hz, rate_hz;
    std::uint32_t divisor;
  };
  const Case cases[] = {{100, 100, 1},
                        {100, 30, 3},
                        {100, 20, 5},
                        {100, 10, 10},
                        {100, 1, 100},
                        {100, 100.0 / 3.0, 3},
                        {50, 50, 1},
                        {50, 30, 1},
                        {50, 20, 2},
                        {50, 10, 5},
                        {1000, 30, 33},
                        {2, 0.5, 4},
                        // 100 / (100 / 11) is 10.999999999999998 in doubles: the 1e-9 makes it 11.
                        {100, 100.0 / 11.0, 11},
                        {50, 50.0 / 22.0, 22}};
  auto table = std::make_unique<TaskTable>();
  for (const Case& c : cases) {
    EXPECT_EQ(TaskTable::divisor_for(c.tick_hz, c.rate_hz), c.divisor)
        << c.rate_hz << " Hz of " << c.tick_hz;
    ASSERT_TRUE(table->init(c.tick_hz).is_ok());
    ASSERT_TRUE(table->add(plain("t", c.rate_hz)).is_ok()) << c.rate_hz << " Hz of " << c.tick_hz;
    const TaskCounters k = table->counters(0);
    EXPECT_EQ(k.divisor, c.divisor) << c.rate_hz << " Hz of " << c.tick_hz;
    EXPECT_DOUBLE_EQ(k.rate_hz, c.rate_hz);
  }
}

TEST_F(TaskTableTest, ScheduleAt50HzTick) {
  ASSERT_TRUE(table->init(50.0, &log).is_ok());
  Probe camera = probe(10);
  Probe lidar = probe(10);
  ASSERT_TRUE(table->add(spec("camera", 30.0, 0, 1000, &camera)).is_ok());
  ASSERT_TRUE(table->add(spec("lidar", 20.0, 1, 1000, &lidar)).is_ok());
  run_ticks(0, 6);
  EXPECT_EQ(camera.ran_on, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(lidar.ran_on, (std::vector<std::uint64_t>{1, 3, 5}));
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
  ASSERT_TRUE(table->add(TaskSpec{"a", 100, 0, 1, Severity::Warning, &Tag::run, &a}).is_ok());
  ASSERT_TRUE(table->add(TaskSpec{"b", 50, 1, 1, Severity::Warning, &Tag::run, &b}).is_ok());
  ASSERT_TRUE(table->add(TaskSpec{"c", 100, 0, 1, Severity::Warning, &Tag::run, &c}).is_ok());
  run_tick(0);
  run_tick(1);
  EXPECT_EQ(order, (std::vector<int>{1, 3, 1, 2, 3}));
}

// --- counters -------------------------------------------------------------------------------

TEST_F(TaskTableTest, OverrunCountedOnlyOverBudget) {
  Probe slow = probe(1500);   // 1.5 us against a 1 us budget
  Probe fast = probe(400);    // 0.4 us against a 1 us budget
  Probe exact = probe(1000);  // exactly at budget: not an overrun
  ASSERT_TRUE(table->add(spec("slow", 100, 0, 1000, &slow)).is_ok());
  ASSERT_TRUE(table->add(spec("fast", 100, 0, 1000, &fast)).is_ok());
  ASSERT_TRUE(table->add(spec("exact", 100, 0, 1000, &exact)).is_ok());
  run_ticks(0, 4);
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
  ASSERT_TRUE(table->add(spec("varying", 100, 0, 50'000, &p)).is_ok());
  // Costs 10, 60, 20, 80 us: two over the 50 us budget.
  const hal::TimeNs costs[] = {10'000, 60'000, 20'000, 80'000};
  for (std::uint64_t t = 0; t < 4; ++t) {
    p.cost_ns = costs[t];
    run_tick(t);
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
  ASSERT_TRUE(table->add(spec("estimator", 20.0, 3, 250'000, &p)).is_ok());
  const TaskCounters c = table->counters(0);
  EXPECT_STREQ(c.name, "estimator");
  EXPECT_DOUBLE_EQ(c.rate_hz, 20.0);
  EXPECT_EQ(c.divisor, 5U);
  EXPECT_EQ(c.offset, 3U);
  EXPECT_DOUBLE_EQ(c.budget_us, 250.0);
  EXPECT_EQ(c.runs, 0U);
  EXPECT_EQ(c.overruns, 0U);
  EXPECT_EQ(c.overrun_events, 0U);
  EXPECT_EQ(c.max_us, 0.0);
}

// --- init errors: every one names the task (or the table) and the field ----------------------

// The message names the table, the task and the field, and contains each of the fragments.
void expect_error(const Status& s, std::initializer_list<const char*> fragments) {
  ASSERT_FALSE(s.is_ok());
  const std::string m = s.message();
  for (const char* f : fragments) EXPECT_NE(m.find(f), std::string::npos) << f << " in: " << m;
}

TEST(TaskTableInitTest, BadTickRateRefused) {
  auto table = std::make_unique<TaskTable>();
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_error(table->init(0.0), {"task table", "tick_rate_hz", "0 Hz", "expected"});
  expect_error(table->init(-100.0), {"tick_rate_hz", "-100 Hz"});
  expect_error(table->init(nan), {"tick_rate_hz", "nan Hz"});
  expect_error(table->init(inf), {"tick_rate_hz", "inf Hz"});
  expect_error(table->init(2e6), {"tick_rate_hz", "2e+06 Hz", "1e+06 Hz"});
  EXPECT_DOUBLE_EQ(table->tick_rate_hz(), 0.0);
  // Nothing can be added to a table whose init failed.
  expect_error(table->add(plain("camera")), {"'camera'", "not initialised"});
  EXPECT_EQ(table->size(), 0U);
}

TEST(TaskTableInitTest, BadThrottleRefused) {
  auto table = std::make_unique<TaskTable>();
  expect_error(table->init(100.0, nullptr, 0.0), {"overrun_throttle_s", "0 s", "0.01", "3600 s"});
  expect_error(table->init(100.0, nullptr, 0.005), {"overrun_throttle_s", "0.005 s"});
  expect_error(table->init(100.0, nullptr, 1e9), {"overrun_throttle_s"});
  expect_error(table->init(100.0, nullptr, std::numeric_limits<double>::quiet_NaN()),
               {"overrun_throttle_s", "nan s"});
  ASSERT_TRUE(table->init(100.0, nullptr, 0.01).is_ok());  // one tick: every overrun reported
  EXPECT_EQ(table->throttle_ticks(), 1U);
  ASSERT_TRUE(table->init(100.0, nullptr, 0.5).is_ok());
  EXPECT_EQ(table->throttle_ticks(), 50U);
  ASSERT_TRUE(table->init(100.0).is_ok());
  EXPECT_EQ(table->throttle_ticks(), 100U);  // default: 1 s of tick time
}

TEST_F(TaskTableTest, BadRateRefused) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_error(table->add(plain("camera", 0.0)),
               {"task table", "'camera'", "rate_hz", "0 Hz", "expected", "100 Hz"});
  expect_error(table->add(plain("camera", -30.0)), {"'camera'", "rate_hz", "-30 Hz"});
  expect_error(table->add(plain("camera", nan)), {"'camera'", "rate_hz", "nan Hz"});
  expect_error(table->add(plain("camera", inf)), {"'camera'", "rate_hz", "inf Hz"});
  // Faster than the tick cannot be scheduled.
  expect_error(table->add(plain("camera", 100.5)), {"'camera'", "rate_hz", "100.5 Hz", "100 Hz"});
  // So slow that the divisor would not fit 32 bits.
  expect_error(table->add(plain("camera", 1e-9)), {"'camera'", "rate_hz", "1e-09 Hz"});
  EXPECT_EQ(table->size(), 0U);
  EXPECT_TRUE(table->add(plain("camera", 100.0)).is_ok());  // exactly the tick rate is fine
}

TEST_F(TaskTableTest, OffsetNotBelowDivisorRefused) {
  // 20 Hz of 100 Hz: divisor 5, offsets 0 to 4.
  expect_error(table->add(plain("lidar", 20.0, 5)),
               {"'lidar'", "offset", "5 ticks", "0 to 4 ticks", "divisor 5"});
  expect_error(table->add(plain("lidar", 20.0, 9)), {"'lidar'", "offset", "9 ticks"});
  expect_error(table->add(plain("health", 100.0, 1)), {"'health'", "offset", "0 to 0 ticks"});
  EXPECT_EQ(table->size(), 0U);
  EXPECT_TRUE(table->add(plain("lidar", 20.0, 4)).is_ok());  // the largest valid offset
}

TEST_F(TaskTableTest, NonPositiveBudgetRefused) {
  expect_error(table->add(plain("odometry", 100.0, 0, 0)),
               {"'odometry'", "budget_ns", "0 ns", "above 0 ns"});
  expect_error(table->add(plain("odometry", 100.0, 0, -20'000)),
               {"'odometry'", "budget_ns", "-20000 ns"});
  EXPECT_EQ(table->size(), 0U);
}

TEST_F(TaskTableTest, NullFunctionRefused) {
  TaskSpec s = plain("behavior");
  s.fn = nullptr;
  expect_error(table->add(s), {"'behavior'", "fn", "null"});
  EXPECT_EQ(table->size(), 0U);
  s.fn = &noop;
  EXPECT_TRUE(table->add(s).is_ok());  // a null ctx is fine
}

TEST_F(TaskTableTest, DuplicateNameRefused) {
  ASSERT_TRUE(table->add(plain("health")).is_ok());
  ASSERT_TRUE(table->add(plain("odometry")).is_ok());
  // Same text in another buffer: names are compared by content, not pointer.
  char copy[] = "odometry";
  expect_error(table->add(plain(copy)), {"'odometry'", "name", "task #1", "unique"});
  EXPECT_EQ(table->size(), 2U);
}

TEST_F(TaskTableTest, MissingNameRefused) {
  expect_error(table->add(plain(nullptr)), {"task #0", "name", "empty"});
  expect_error(table->add(plain("")), {"task #0", "name", "empty"});
  EXPECT_EQ(table->size(), 0U);
}

TEST_F(TaskTableTest, ThirteenthTaskRefusedNamingTheCapacity) {
  static_assert(TaskTable::kMaxTasks == 12);
  static const char* const names[] = {"t0", "t1", "t2", "t3", "t4",  "t5",
                                      "t6", "t7", "t8", "t9", "t10", "t11"};
  for (const char* n : names) EXPECT_TRUE(table->add(plain(n)).is_ok()) << n;
  EXPECT_EQ(table->size(), 12U);
  expect_error(table->add(plain("13th")), {"'13th'", "full", "capacity 12 tasks"});
  EXPECT_EQ(table->size(), 12U);
}

TEST_F(TaskTableTest, InitClearsTheTable) {
  ASSERT_TRUE(table->add(plain("a")).is_ok());
  ASSERT_TRUE(table->init(50.0).is_ok());
  EXPECT_EQ(table->size(), 0U);
  EXPECT_TRUE(table->add(plain("a", 50.0)).is_ok());
}

TEST(TaskTableLabelTest, LabelNamesTheTableInErrors) {
  auto table = std::make_unique<TaskTable>("slow rate group");
  expect_error(table->init(-1.0), {"slow rate group: tick_rate_hz"});
}

// --- overrun events -------------------------------------------------------------------------

// 5 overruns within 1 s: one event at once, the 4 held back reported in one event when the
// interval is over, with the longest of them; nothing more while the task keeps its budget.
TEST_F(TaskTableTest, OverrunEventsThrottledPerInterval) {
  Probe p = probe(0);
  ASSERT_TRUE(table->add(spec("perception", 100, 0, 1000, &p)).is_ok());
  ASSERT_EQ(table->throttle_ticks(), 100U);
  const hal::TimeNs costs[] = {2000, 3000, 7000, 4000, 5000};  // all over the 1 us budget
  for (std::uint64_t t = 0; t < 5; ++t) {
    p.cost_ns = costs[t];
    run_tick(t);
  }
  p.cost_ns = 500;  // within budget from here on
  run_ticks(5, 100);
  std::vector<Event> ev = drain();
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].kind, EventKind::Overrun);
  EXPECT_STREQ(ev[0].task, "perception");
  EXPECT_EQ(ev[0].count, 1U);
  EXPECT_DOUBLE_EQ(ev[0].took_us, 2.0);
  EXPECT_DOUBLE_EQ(ev[0].budget_us, 1.0);
  EXPECT_EQ(ev[0].t_ns, 0);

  run_tick(100);  // 1 s after the first event
  ev = drain();
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].count, 4U);            // the suppressed ones
  EXPECT_DOUBLE_EQ(ev[0].took_us, 7.0);  // the longest of them
  EXPECT_EQ(ev[0].t_ns, 100 * kTickNs);

  run_ticks(101, 400);
  EXPECT_TRUE(drain().empty());
  const TaskCounters c = table->counters(0);
  EXPECT_EQ(c.overruns, 5U);  // every overrun counted, throttled or not
  EXPECT_EQ(c.overrun_events, 2U);
}

// The held-back count is reported when the interval ends, also on a tick the task does not run.
TEST_F(TaskTableTest, HeldBackOverrunsReportedOnTheTickTheIntervalEnds) {
  ASSERT_TRUE(table->init(kTickHz, &log, 0.33).is_ok());  // 33 ticks
  Probe p = probe(2000);
  ASSERT_TRUE(table->add(spec("lidar", 20, 1, 1000, &p)).is_ok());  // ticks 1, 6, 11, ...
  run_ticks(0, 7);  // overruns on ticks 1 (reported) and 6 (held back)
  p.cost_ns = 500;
  run_ticks(7, 34);
  ASSERT_EQ(drain().size(), 1U);
  run_tick(34);  // 33 ticks after tick 1; the task is not due (34 % 5 == 4)
  const std::vector<Event> ev = drain();
  ASSERT_EQ(ev.size(), 1U);
  EXPECT_EQ(ev[0].count, 1U);
  EXPECT_EQ(ev[0].t_ns, 34 * kTickNs);
}

// A task that overruns on every tick gets one event per second, each counting a second's worth.
TEST_F(TaskTableTest, SteadyOverrunsGiveOneEventPerInterval) {
  Probe p = probe(2000);
  ASSERT_TRUE(table->add(spec("lidar", 20, 1, 1000, &p)).is_ok());  // ticks 1, 6, 11, ...
  run_ticks(0, 300);
  const std::vector<Event> ev = drain();
  ASSERT_EQ(ev.size(), 3U);
  EXPECT_EQ(ev[0].t_ns, 1 * kTickNs);
  EXPECT_EQ(ev[0].count, 1U);
  EXPECT_EQ(ev[1].t_ns, 101 * kTickNs);  // the overrun on tick 101 reported with those before
  EXPECT_EQ(ev[1].count, 20U);
  EXPECT_EQ(ev[2].t_ns, 201 * kTickNs);
  EXPECT_EQ(ev[2].count, 20U);
  EXPECT_EQ(table->counters(0).overruns, 60U);
}

TEST_F(TaskTableTest, ThrottleIsConfigurableAndPerTask) {
  ASSERT_TRUE(table->init(kTickHz, &log, 0.25).is_ok());
  Probe a = probe(2000);
  Probe b = probe(2000);
  ASSERT_TRUE(table->add(spec("a", 100, 0, 1000, &a)).is_ok());
  ASSERT_TRUE(table->add(spec("b", 100, 0, 1000, &b)).is_ok());
  run_ticks(0, 50);
  const std::vector<Event> ev = drain();
  // Each task: ticks 0 and 25 (every 0.25 s), independently of the other.
  ASSERT_EQ(ev.size(), 4U);
  EXPECT_STREQ(ev[0].task, "a");
  EXPECT_STREQ(ev[1].task, "b");
  EXPECT_STREQ(ev[2].task, "a");
  EXPECT_EQ(ev[2].count, 25U);
  EXPECT_EQ(ev[2].t_ns, 25 * kTickNs);
  EXPECT_STREQ(ev[3].task, "b");
}

TEST_F(TaskTableTest, OverrunSeverityPropagated) {
  Probe warn = probe(2000);
  Probe err = probe(2000);
  Probe info = probe(2000);
  ASSERT_TRUE(table->add(spec("telemetry", 100, 0, 1000, &warn)).is_ok());  // default
  ASSERT_TRUE(table->add(spec("health", 100, 0, 1000, &err, Severity::Error)).is_ok());
  ASSERT_TRUE(table->add(spec("log", 100, 0, 1000, &info, Severity::Info)).is_ok());
  run_tick(0);
  const std::vector<Event> ev = drain();
  ASSERT_EQ(ev.size(), 3U);
  EXPECT_EQ(ev[0].severity, Severity::Warning);
  EXPECT_EQ(ev[1].severity, Severity::Error);
  EXPECT_EQ(ev[2].severity, Severity::Info);
}

TEST_F(TaskTableTest, NoSinkStillCounts) {
  ASSERT_TRUE(table->init(kTickHz).is_ok());
  Probe p = probe(2000);
  ASSERT_TRUE(table->add(spec("a", 100, 0, 1000, &p)).is_ok());
  run_ticks(0, 250);
  EXPECT_EQ(table->counters(0).overruns, 250U);
  EXPECT_EQ(table->counters(0).overrun_events, 0U);
  EXPECT_EQ(log.size(), 0U);
}

// --- bind -----------------------------------------------------------------------------------

struct Counter {
  int calls = 0;
  void tick() { ++calls; }
};

TEST_F(TaskTableTest, BindCallsMemberFunction) {
  Counter a, b;
  ASSERT_TRUE(table->add(TaskSpec::bind<&Counter::tick>("a", 100.0, 0, 1000, &a)).is_ok());
  ASSERT_TRUE(table->add(TaskSpec::bind<&Counter::tick>("b", 50.0, 1, 1000, &b)).is_ok());
  const TaskSpec s = TaskSpec::bind<&Counter::tick>("direct", 25.0, 2, 7, &a);
  EXPECT_STREQ(s.name, "direct");
  EXPECT_DOUBLE_EQ(s.rate_hz, 25.0);
  EXPECT_EQ(s.offset, 2U);
  EXPECT_EQ(s.budget_ns, 7);
  EXPECT_EQ(s.overrun_severity, Severity::Warning);
  EXPECT_EQ(s.ctx, &a);
  const TaskSpec e = TaskSpec::bind<&Counter::tick>("err", 25.0, 0, 7, &a, Severity::Error);
  EXPECT_EQ(e.overrun_severity, Severity::Error);
  run_ticks(0, 6);
  EXPECT_EQ(a.calls, 6);
  EXPECT_EQ(b.calls, 3);  // ticks 1, 3, 5
  s.fn(s.ctx);
  EXPECT_EQ(a.calls, 7);
}

// bind() with an integer rate (an old divisor, most likely) does not compile.
template <typename R>
concept BindsWithRate = requires(R r, Counter* c) {
  TaskSpec::bind<&Counter::tick>("x", r, 0, 1, c);
};
static_assert(BindsWithRate<double>);
static_assert(BindsWithRate<float>);
static_assert(!BindsWithRate<int>);
static_assert(!BindsWithRate<std::uint32_t>);

}  // namespace
}  // namespace carril::fw
