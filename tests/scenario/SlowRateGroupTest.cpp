// The slow rate group in the simulator: it runs in lockstep with the control loop (every
// slow_divisor ticks), reads the status the telemetry task handed over through the TripleBuffer,
// and never changes what the robot does: the same seed gives the same trajectory and the same
// status lines.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_sim/app/SimRun.hpp"
#include "tests/scenario/ScenarioSupport.hpp"

namespace carril::sim {
namespace {

TEST(SlowRateGroupSim, RunsInLockstepAndWritesOneStatusLineASecond) {
  const Scenario s = test::load_repo_scenario("square");
  SimRun run(s, 1);
  while (run.sim_time_s() < 10.0 - 1e-9 && run.step()) {
  }
  const SimTopology& t = run.topology();
  EXPECT_EQ(t.slow_divisor, 20U);  // 5 Hz on a 100 Hz tick
  EXPECT_EQ(t.slow.cycles(), 50U);
  const std::vector<std::string>& lines = t.console.lines();
  ASSERT_EQ(lines.size(), 10U);
  // Cycle 0 runs after tick 19, which published the status at loop time 0.19 s.
  EXPECT_EQ(lines[0].rfind("status     0.190 s  ", 0), 0U) << lines[0];
  EXPECT_NE(lines[0].find("ticks 19 "), std::string::npos) << lines[0];
  EXPECT_EQ(lines[9].rfind("status     9.190 s  active FOLLOW/track", 0), 0U) << lines[9];
  EXPECT_NE(lines[9].find("fault none"), std::string::npos) << lines[9];
}

TEST(SlowRateGroupSim, SameSeedSameStatusLines) {
  const Scenario s = test::load_repo_scenario("square");
  std::vector<std::string> first;
  for (int i = 0; i < 2; ++i) {
    SimRun run(s, 3);
    while (run.sim_time_s() < 5.0 - 1e-9 && run.step()) {
    }
    std::vector<std::string> lines = run.topology().console.lines();
    // The tick's compute time (max us) is real time: the one part that may differ.
    for (std::string& l : lines) l = l.substr(0, l.find("(overruns"));
    if (i == 0) {
      first = lines;
    } else {
      EXPECT_EQ(lines, first);
    }
  }
  EXPECT_EQ(first.size(), 5U);
}

}  // namespace
}  // namespace carril::sim
