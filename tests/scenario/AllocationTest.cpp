// Static allocation, proven: this binary replaces the global allocators (operator new in all its
// forms, malloc, calloc, realloc, memalign, aligned_alloc, posix_memalign, valloc, pvalloc) with
// counting versions (host_sim/alloc) and runs whole missions through every behaviour state:
// corners with camera noise (START, FOLLOW, AVOID round two obstacles, END on the mark: more
// than 10,000 ticks), a tape that ends (SEARCH, then FAULT line_not_found), and injected drive
// and sensor faults (FAULT, health rules). Not one allocation may happen inside a tick after
// init; Eigen's runtime no-malloc check is armed inside ticks too (it aborts where asserts are
// compiled in).
#include <gtest/gtest.h>

#include <malloc.h>
#include <Eigen/Core>

#include <functional>
#include <set>
#include <string>
#include <vector>

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
    // The page-aligned ones too.
    alloc::begin_window();
    void* v = valloc(64);
    escape(v);
    void* pv = pvalloc(64);
    escape(pv);
    alloc::end_window();
    std::free(v);
    std::free(pv);
    EXPECT_EQ(alloc::count_in_windows() - before, 4U);
  }
}

// Runs `run` to its end; returns the behaviour states it went through (trajectory rows).
std::set<std::string> states_of(SimRun& run, long& ticks) {
  ticks = 0;
  while (run.step()) ++ticks;
  ++ticks;
  std::set<std::string> seen;
  for (const TrajectoryRow& r : run.rows()) seen.insert(r.state);
  return seen;
}

TEST(AllocationTest, NoHeapAllocationInAnyStateOfAWholeMission) {
  Scenario s = test::load_repo_scenario("corners");
  s.robot.camera.noise_std = 4.0;
  SimRun run(s, s.seed);
  long ticks = 0;
  const std::set<std::string> seen = states_of(run, ticks);
  EXPECT_GE(ticks, 10000);
  EXPECT_EQ(seen, (std::set<std::string>{"START", "FOLLOW", "AVOID", "END"}));
  EXPECT_EQ(run.summary(1.0).result, "end_reached");
  EXPECT_EQ(run.topology().firmware->mission_counter("obstacles_avoided"), 2U);
  EXPECT_EQ(run.allocations_in_ticks(), 0U);
}

TEST(AllocationTest, NoHeapAllocationInSearchAndItsFault) {
  const Scenario s = test::tape_end_scenario();
  SimRun run(s, 1);
  long ticks = 0;
  const std::set<std::string> seen = states_of(run, ticks);
  EXPECT_EQ(seen, (std::set<std::string>{"START", "FOLLOW", "SEARCH", "FAULT"}));
  EXPECT_EQ(run.summary(1.0).fault, "line_not_found");
  EXPECT_EQ(run.allocations_in_ticks(), 0U);
}

TEST(AllocationTest, HealthFaultPathsAllocateNothing) {
  const std::vector<std::function<void(SimTopology&)>> faults = {
      [](SimTopology& t) { t.scanner.inject_fault(hal::SimSensorFault::NanRanges); },
      [](SimTopology& t) { t.camera.inject_fault(hal::SimSensorFault::Frozen); },
      [](SimTopology& t) { t.camera.inject_fault(hal::SimSensorFault::Blank); },
      [](SimTopology& t) { t.imu.inject_fault(hal::SimSensorFault::Frozen); },
      [](SimTopology& t) { t.imu.inject_fault(hal::SimSensorFault::OutOfRange); },
  };
  const Scenario s = test::load_repo_scenario("corners");
  for (const auto& inject : faults) {
    SimRun run(s, s.seed);
    while (run.sim_time_s() < 3.0 && run.step()) {
    }
    inject(run.topology());
    while (run.step()) {
    }
    EXPECT_EQ(run.summary(1.0).result, "fault");
    EXPECT_EQ(run.allocations_in_ticks(), 0U);
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
