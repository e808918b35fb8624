#include "hal/linux/PeriodicThread.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

namespace carril::hal {
namespace {

// No timing asserts: on shared, loaded machines periods stretch. Only that it runs and stops.
constexpr TimeNs k100Hz = 10'000'000;  // [ns]

void count(void* ctx) {
  static_cast<std::atomic<int>*>(ctx)->fetch_add(1);
}

// Waits (up to 10 s) until the thread has run n cycles.
bool wait_for_cycles(const PeriodicThread& t, std::uint64_t n) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (t.cycles() < n) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

TEST(PeriodicThreadTest, RunsCyclesAt100HzAndStopsCleanly) {
  std::atomic<int> calls{0};
  PeriodicThread t;
  EXPECT_EQ(t.policy(), PeriodicThread::Policy::None);
  ASSERT_TRUE(t.start("carril-test", k100Hz, 0, &count, &calls)) << t.note();
  EXPECT_TRUE(t.running());
  EXPECT_EQ(t.policy(), PeriodicThread::Policy::Other);  // priority 0 asks for SCHED_OTHER
  EXPECT_STREQ(t.note(), "");
  EXPECT_TRUE(wait_for_cycles(t, 5));
  t.stop();
  EXPECT_FALSE(t.running());
  EXPECT_GE(t.cycles(), 5U);
  EXPECT_EQ(std::uint64_t(calls.load()), t.cycles());
  // Stopped means stopped: nothing runs after stop() returned.
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(std::uint64_t(calls.load()), t.cycles());
  t.stop();  // again: a no-op
  RecordProperty("missed_deadlines", std::to_string(t.missed_deadlines()));
}

// What the thread itself runs under, as the kernel sees it.
struct PolicyProbe {
  std::atomic<int> calls{0};
  std::atomic<int> policy{-1};
  static void run(void* ctx) {
    auto* p = static_cast<PolicyProbe*>(ctx);
    p->policy.store(sched_getscheduler(0));  // 0: the calling thread
    p->calls.fetch_add(1);
  }
};

// SCHED_FIFO when permitted, otherwise SCHED_OTHER with the reason in note(): never a failure.
TEST(PeriodicThreadTest, FifoWhenPermittedElseReportedFallback) {
  PolicyProbe probe;
  PeriodicThread t;
  ASSERT_TRUE(t.start("carril-fifo", k100Hz, 10, &PolicyProbe::run, &probe)) << t.note();
  EXPECT_TRUE(wait_for_cycles(t, 3));
  t.stop();
  EXPECT_GT(t.cycles(), 0U);
  if (t.policy() == PeriodicThread::Policy::Fifo) {
    EXPECT_STREQ(t.note(), "");
    EXPECT_EQ(probe.policy.load(), SCHED_FIFO);
  } else {
    EXPECT_EQ(t.policy(), PeriodicThread::Policy::Other);
    EXPECT_NE(std::string(t.note()).find("SCHED_FIFO priority 10 not permitted"), std::string::npos)
        << t.note();
    EXPECT_EQ(probe.policy.load(), SCHED_OTHER);
  }
  RecordProperty("policy", t.policy() == PeriodicThread::Policy::Fifo ? "fifo" : "other");
}

// In a child process: gives up the privilege for SCHED_FIFO (RLIMIT_RTPRIO 0, and not root),
// asks for it, and exits 0 when the thread fell back to SCHED_OTHER, said why and ran.
[[noreturn]] void start_fifo_without_privilege() {
  const rlimit none{0, 0};
  if (setrlimit(RLIMIT_RTPRIO, &none) != 0) std::_Exit(10);
  if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) std::_Exit(11);
  PolicyProbe probe;
  PeriodicThread t;
  if (!t.start("carril-nopriv", k100Hz, 50, &PolicyProbe::run, &probe)) std::_Exit(12);
  if (t.policy() != PeriodicThread::Policy::Other) std::_Exit(13);
  if (std::string(t.note()).find("SCHED_FIFO priority 50 not permitted") == std::string::npos) {
    std::_Exit(14);
  }
  if (!wait_for_cycles(t, 2)) std::_Exit(15);
  t.stop();
  if (probe.policy.load() != SCHED_OTHER) std::_Exit(16);
  std::_Exit(0);
}

// The fallback itself, whatever this machine allows (here root may well get SCHED_FIFO).
TEST(PeriodicThreadDeathTest, FallsBackWithoutPrivilege) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(start_fifo_without_privilege(), ::testing::ExitedWithCode(0), "");
}

TEST(PeriodicThreadTest, BadArgumentsRefused) {
  std::atomic<int> calls{0};
  PeriodicThread t;
  EXPECT_FALSE(t.start("bad", 0, 0, &count, &calls));
  EXPECT_NE(std::string(t.note()).find("period 0 ns"), std::string::npos) << t.note();
  EXPECT_FALSE(t.start("bad", -5, 0, &count, &calls));
  EXPECT_FALSE(t.start("bad", k100Hz, 100, &count, &calls));
  EXPECT_NE(std::string(t.note()).find("priority 100"), std::string::npos) << t.note();
  EXPECT_FALSE(t.start("bad", k100Hz, -1, &count, &calls));
  EXPECT_FALSE(t.start("bad", k100Hz, 0, nullptr, &calls));
  EXPECT_NE(std::string(t.note()).find("fn null"), std::string::npos) << t.note();
  EXPECT_FALSE(t.running());
  EXPECT_EQ(t.cycles(), 0U);
}

TEST(PeriodicThreadTest, SecondStartRefusedWhileRunningRestartAfterStop) {
  std::atomic<int> calls{0};
  PeriodicThread t;
  ASSERT_TRUE(t.start("carril-a", k100Hz, 0, &count, &calls));
  EXPECT_FALSE(t.start("carril-b", k100Hz, 0, &count, &calls));
  EXPECT_NE(std::string(t.note()).find("already running"), std::string::npos) << t.note();
  EXPECT_TRUE(t.running());
  t.stop();
  const int before = calls.load();
  ASSERT_TRUE(t.start("a-name-longer-than-15-characters", k100Hz, 0, &count, &calls)) << t.note();
  EXPECT_TRUE(wait_for_cycles(t, 1));
  t.stop();
  EXPECT_GT(t.cycles(), 0U);
  EXPECT_EQ(t.cycles(), std::uint64_t(calls.load() - before));  // counts restart from 0
}

TEST(PeriodicThreadTest, DestructorStops) {
  std::atomic<int> calls{0};
  {
    PeriodicThread t;
    ASSERT_TRUE(t.start("carril-scope", k100Hz, 0, &count, &calls));
    EXPECT_TRUE(wait_for_cycles(t, 1));
  }
  const int after = calls.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(calls.load(), after);
}

}  // namespace
}  // namespace carril::hal
