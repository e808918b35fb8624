#include "firmware/core/FixedRateLoop.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace carril::fw {
namespace {

constexpr hal::TimeNs kPeriod = 10'000'000;    // 10 ms
constexpr hal::TimeNs kStart = 5'000'000'000;  // arbitrary loop-time origin (5 s)

// Loop time that only moves when told: sleeping jumps to the deadline (never back), and a step
// "takes time" by advancing now_ns itself.
class FakeLoopClock final : public hal::Clock {
 public:
  hal::TimeNs now_ns() const override { return now; }
  hal::TimeNs cpu_now_ns() const override { return now; }
  void sleep_until_ns(hal::TimeNs t) override {
    sleeps.push_back(t);
    if (t > now) now = t;
  }

  hal::TimeNs now = kStart;
  std::vector<hal::TimeNs> sleeps;
};

TEST(FixedRateLoopTest, DeadlinesAreAbsolute) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<hal::TimeNs> calls;
  const LoopStats st = loop.run(
      [&] {
        calls.push_back(clock.now);
        clock.now += kPeriod * 3 / 10;  // each step takes 30% of the period
        return true;
      },
      8);
  EXPECT_EQ(st.periods, 8U);
  EXPECT_EQ(st.missed_deadlines, 0U);
  ASSERT_EQ(calls.size(), 8U);
  // Step k starts at exactly start + k * period: the 3 ms of work never shifts the grid.
  for (std::size_t k = 0; k < calls.size(); ++k) {
    EXPECT_EQ(calls[k], kStart + static_cast<hal::TimeNs>(k) * kPeriod) << "step " << k;
  }
  // Every sleep targets the next grid point.
  for (std::size_t k = 0; k < clock.sleeps.size(); ++k) {
    EXPECT_EQ(clock.sleeps[k], kStart + static_cast<hal::TimeNs>(k + 1) * kPeriod);
  }
}

TEST(FixedRateLoopTest, JitteryStepsDoNotDrift) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<hal::TimeNs> calls;
  const hal::TimeNs costs[] = {1'000'000, 9'999'999, 0, 4'500'000, 7'000'000, 10'000'000, 3};
  std::size_t i = 0;
  const LoopStats st = loop.run(
      [&] {
        calls.push_back(clock.now);
        clock.now += costs[i++ % 7];
        return true;
      },
      7);
  // A step that takes exactly one period finishes on the next deadline: not a miss.
  EXPECT_EQ(st.missed_deadlines, 0U);
  ASSERT_EQ(calls.size(), 7U);
  for (std::size_t k = 0; k < calls.size(); ++k) {
    EXPECT_EQ(calls[k], kStart + static_cast<hal::TimeNs>(k) * kPeriod) << "step " << k;
  }
}

TEST(FixedRateLoopTest, OverrunSkipsMissedPeriodsAndResumesOnGrid) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<hal::TimeNs> calls;
  const LoopStats st = loop.run(
      [&] {
        calls.push_back(clock.now);
        if (calls.size() == 2) {
          // Step 1 starts at 1 P and its deadline is 2 P; it finishes at 4.5 P, 2.5 periods
          // late, so the deadlines at 2 P, 3 P and 4 P are lost. The next one is 5 P.
          clock.now += kPeriod * 35 / 10;
        } else {
          clock.now += kPeriod / 10;
        }
        return true;
      },
      5);
  EXPECT_EQ(st.periods, 5U);
  EXPECT_EQ(st.missed_deadlines, 3U);
  ASSERT_EQ(calls.size(), 5U);
  EXPECT_EQ(calls[0], kStart + 0 * kPeriod);
  EXPECT_EQ(calls[1], kStart + 1 * kPeriod);
  EXPECT_EQ(calls[2], kStart + 5 * kPeriod);
  EXPECT_EQ(calls[3], kStart + 6 * kPeriod);
  EXPECT_EQ(calls[4], kStart + 7 * kPeriod);
  // No burst to catch up: never asked to sleep to a time already past.
  for (std::size_t k = 1; k < clock.sleeps.size(); ++k) {
    EXPECT_GT(clock.sleeps[k], clock.sleeps[k - 1]);
  }
}

TEST(FixedRateLoopTest, SmallOverrunMissesOneDeadline) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<hal::TimeNs> calls;
  const LoopStats st = loop.run(
      [&] {
        calls.push_back(clock.now);
        clock.now += calls.size() == 1 ? kPeriod + 1 : 0;  // 1 ns late on the first step
        return true;
      },
      3);
  EXPECT_EQ(st.missed_deadlines, 1U);
  ASSERT_EQ(calls.size(), 3U);
  EXPECT_EQ(calls[1], kStart + 2 * kPeriod);
  EXPECT_EQ(calls[2], kStart + 3 * kPeriod);
}

TEST(FixedRateLoopTest, OverrunEndingExactlyOnADeadlineStillMeetsIt) {
  // The first step takes exactly two periods: it misses the deadline at +1 period and ends
  // exactly on the one at +2, which therefore still counts as met.
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<hal::TimeNs> calls;
  const LoopStats st = loop.run(
      [&] {
        calls.push_back(clock.now);
        clock.now += calls.size() == 1 ? 2 * kPeriod : 0;
        return true;
      },
      3);
  EXPECT_EQ(st.missed_deadlines, 1U);
  ASSERT_EQ(calls.size(), 3U);
  EXPECT_EQ(calls[1], kStart + 2 * kPeriod);
  EXPECT_EQ(calls[2], kStart + 3 * kPeriod);
}

TEST(FixedRateLoopTest, StepReturningFalseStops) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  int calls = 0;
  const LoopStats st = loop.run([&] { return ++calls < 4; });  // no period limit
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(st.periods, 4U);  // the final (false) step counts as a period
  EXPECT_EQ(st.missed_deadlines, 0U);
  // No sleep after the last step.
  ASSERT_EQ(clock.sleeps.size(), 3U);
  EXPECT_EQ(clock.now, kStart + 3 * kPeriod);
}

TEST(FixedRateLoopTest, MaxPeriodsHonoured) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  int calls = 0;
  const LoopStats st = loop.run(
      [&] {
        ++calls;
        return true;
      },
      6);
  EXPECT_EQ(calls, 6);
  EXPECT_EQ(st.periods, 6U);

  calls = 0;
  const LoopStats one = loop.run(
      [&] {
        ++calls;
        return true;
      },
      1);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(one.periods, 1U);
}

// A clock whose sleeps oversleep by a set amount: the OS waking the loop late.
class LateWakeClock final : public hal::Clock {
 public:
  hal::TimeNs now_ns() const override { return now; }
  hal::TimeNs cpu_now_ns() const override { return now; }
  void sleep_until_ns(hal::TimeNs t) override {
    const hal::TimeNs late = lateness[std::size_t(sleeps++) % lateness.size()];
    if (t + late > now) now = t + late;
  }
  hal::TimeNs now = kStart;
  int sleeps = 0;
  std::vector<hal::TimeNs> lateness;
};

TEST(FixedRateLoopTest, WakeLatencyIsMeasuredAfterEachDeadline) {
  LateWakeClock clock;
  // 101 periods, one sleep after each: 99 wakes 20 us late, 2 (sleeps 10 and 60) 700 us late.
  clock.lateness.assign(50, 20'000);
  clock.lateness[10] = 700'000;
  FixedRateLoop loop(clock, kPeriod);
  const LoopStats st = loop.run([] { return true; }, 101);
  EXPECT_EQ(st.periods, 101U);
  EXPECT_EQ(loop.missed_deadlines(), 0U);
  const LatencyStats& w = loop.wake_latency();
  EXPECT_EQ(w.count(), 101U);
  EXPECT_DOUBLE_EQ(w.percentile_us(0.5), 21.0);  // the upper edge of the 1 us bin of 20 us
  EXPECT_DOUBLE_EQ(w.percentile_us(0.99), 700.0);
  EXPECT_DOUBLE_EQ(w.max_us(), 700.0);
}

TEST(FixedRateLoopTest, MissedDeadlinesAreCountedWhileRunning) {
  FakeLoopClock clock;
  FixedRateLoop loop(clock, kPeriod);
  std::vector<std::uint64_t> seen;
  int k = 0;
  loop.run(
      [&] {
        seen.push_back(loop.missed_deadlines());
        if (k++ == 2) clock.now += kPeriod * 5 / 2;  // overrun: misses 2 deadlines
        return true;
      },
      6);
  EXPECT_EQ(seen, (std::vector<std::uint64_t>{0, 0, 0, 2, 2, 2}));
}

}  // namespace
}  // namespace carril::fw
