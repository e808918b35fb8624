#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

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

}  // namespace carril::sim::test
