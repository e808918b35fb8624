#pragma once
// Small scenarios built in code for simulator unit tests (loaded through the real loader so the
// robot presets apply exactly as in a run).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim::test {

inline std::string robots_dir() {
  const char* d = std::getenv("CARRIL_ROBOTS_DIR");
  return d ? d : std::string(CARRIL_SOURCE_DIR) + "/config/robots";
}

inline Scenario load_text(const std::string& yaml) {
  LoadResult r = load_scenario_text(yaml, "test.yaml", robots_dir());
  EXPECT_TRUE(r.ok) << r.error;
  return r.scenario;
}

// A robot of `preset` at the origin facing a 1 m box whose near face is 2.5 m ahead.
inline Scenario box_scenario(const char* preset, const char* extra = "") {
  std::string yaml = std::string(R"(
name: lidar_box
duration_s: 1
robot: {preset: )") + preset +
                     R"(}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-20, -20], [-19, -20]]}]
obstacles: [{shape: box, x: 3.0, y: 0.0, size_m: [1.0, 1.0]}]
)" + extra;
  return load_text(yaml);
}

}  // namespace carril::sim::test
