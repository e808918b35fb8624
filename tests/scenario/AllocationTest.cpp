// Static allocation, proven: this binary replaces the global allocators with counting versions
// (host_sim/alloc) and runs a full scenario for more than 10,000 ticks. Not one allocation may
// happen inside a tick after init; Eigen's runtime no-malloc check is armed inside ticks too
// (it aborts where asserts are compiled in).
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "host_sim/alloc/AllocCounter.hpp"
#include "host_sim/app/SimRun.hpp"
#include "tests/scenario/ScenarioSupport.hpp"

namespace carril::sim {
namespace {

// Keeps the compiler from eliding an allocation/free pair (allowed since C++14).
void escape(void* p) {
  asm volatile("" : : "g"(p) : "memory");
}

TEST(AllocationTest, CounterSeesAnAllocationInsideAWindow) {
  // Control: the counter is live, so a zero below means something.
  const std::uint64_t before = alloc::count_in_windows();
  alloc::begin_window();
  int* p = new int(3);
  escape(p);
  alloc::end_window();
  delete p;
  EXPECT_EQ(alloc::count_in_windows() - before, 1U);
  if (alloc::counts_malloc()) {
    alloc::begin_window();
    void* m = std::malloc(16);
    escape(m);
    alloc::end_window();
    std::free(m);
    EXPECT_EQ(alloc::count_in_windows() - before, 2U);
  }
}

TEST(AllocationTest, NoHeapAllocationInsideTicksOverAFullScenario) {
  Scenario s = test::load_repo_scenario("square");
  s.duration_s = 110.0;  // 11,000 ticks at 100 Hz: more than a lap, so every state is exercised
  s.robot.camera.noise_std = 4.0;
  SimRun run(s, s.seed);
  const std::uint64_t total_before = alloc::count_total();
  long ticks = 0;
  while (run.step()) ++ticks;
  ++ticks;
  EXPECT_GE(ticks, 10000);
  EXPECT_GT(alloc::count_total(), total_before);  // the simulator itself allocates: counting is on
  EXPECT_EQ(run.allocations_in_ticks(), 0U);
  const RunSummary r = run.summary(1.0);
  EXPECT_EQ(r.heap_allocations_after_init, 0);
  EXPECT_GE(r.laps, 1);
}

TEST(AllocationTest, FaultPathAllocatesNothingEither) {
  Scenario s = test::load_repo_scenario("square");
  SimRun run(s, s.seed);
  while (run.sim_time_s() < 3.0 && run.step()) {
  }
  run.topology().drives.inject_fault(0, hal::DriveFault::Overcurrent);
  while (run.step()) {
  }
  EXPECT_EQ(run.summary(1.0).result, "fault");
  EXPECT_EQ(run.allocations_in_ticks(), 0U);
}

}  // namespace
}  // namespace carril::sim
