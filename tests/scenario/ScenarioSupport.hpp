#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "host_sim/app/SimRun.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim::test {

// Loads scenarios/<name>.yaml from the source tree.
inline Scenario load_repo_scenario(const std::string& name) {
  const char* d = std::getenv("CARRIL_ROBOTS_DIR");
  const std::string robots = d ? d : std::string(CARRIL_SOURCE_DIR) + "/config/robots";
  LoadResult r =
      load_scenario(std::string(CARRIL_SOURCE_DIR) + "/scenarios/" + name + ".yaml", robots);
  EXPECT_TRUE(r.ok) << r.error;
  return r.scenario;
}

// Loads a scenario from YAML text (robots from the source tree).
inline Scenario load_yaml(const std::string& text) {
  const char* d = std::getenv("CARRIL_ROBOTS_DIR");
  const std::string robots = d ? d : std::string(CARRIL_SOURCE_DIR) + "/config/robots";
  LoadResult r = load_scenario_text(text, "inline.yaml", robots);
  EXPECT_TRUE(r.ok) << r.error;
  return r.scenario;
}

// A 4 m straight tape that just ends, no end mark, walls round it: the robot follows it, loses
// it at its end, searches (left, right, back: where it sees the tape it came along, backwards)
// and stops with line_not_found.
inline Scenario tape_end_scenario() {
  return load_yaml(R"(name: tape_end
duration_s: 40
seed: 1
floor: {color: [90, 90, 90]}
robot: {preset: campero, start: {x: 0.0, y: 0.0, yaw_deg: 0.0}}
mission: {type: follow_line, strategy: marks, line_color: white, end_color: yellow, speed_mps: 0.5}
lines:
  - {color: white, width_m: 0.05, points: [[0, 0], [4, 0]]}
walls:
  - {points: [[-3, -3], [8, -3], [8, 3], [-3, 3], [-3, -3]], thickness_m: 0.1}
)");
}

// Steps `run` until the firmware is in the state named `state` (e.g. "AVOID": true) or the run
// ends (false).
inline bool run_until_state(SimRun& run, const std::string& state) {
  while (run.step()) {
    if (run.state_name() == state) return true;
  }
  return false;
}

// Simulated time of the first trajectory row in FAULT, or -1.
inline double fault_time_s(const SimRun& run) {
  for (const TrajectoryRow& r : run.rows()) {
    if (std::string(r.state) == "FAULT") return r.t;
  }
  return -1.0;
}

}  // namespace carril::sim::test
