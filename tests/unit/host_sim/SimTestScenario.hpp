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

}  // namespace carril::sim::test
