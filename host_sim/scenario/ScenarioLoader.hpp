#pragma once
#include <string>

#include "host_sim/scenario/Scenario.hpp"
#include "loader/MissionLoader.hpp"
#include "loader/RobotLoader.hpp"

namespace carril::sim {

// Result of loading: either a scenario, or one error message of the form
//   "<file>: <key.path[2].field>: expected <what>, got <what>"
struct LoadResult {
  bool ok = false;
  Scenario scenario;
  std::string error;
};

// Values that replace the file's own before anything is checked (carril_sim --preset/--strategy),
// so every rule holds for them as for the file: an unknown preset or line_priority on a
// differential robot is rejected just the same. An empty string keeps the file's value. A
// rejected load whose overrides were set says so at the end of its message.
struct ScenarioOverrides {
  std::string preset;        // robot.preset
  std::string strategy;      // mission.strategy
  std::string camera_noise;  // robot.camera.noise_std, as written on the command line

  bool empty() const { return preset.empty() && strategy.empty() && camera_noise.empty(); }
};

// Reads a scenario file strictly (unknown, missing, mistyped and out-of-range keys are errors)
// and merges it onto its robot preset, read from <robots_dir>/<preset>.yaml.
LoadResult load_scenario(const std::string& path, const std::string& robots_dir,
                         const ScenarioOverrides& overrides = {});

// Same, from text already in memory; `path` is only used in messages.
LoadResult load_scenario_text(const std::string& text, const std::string& path,
                              const std::string& robots_dir,
                              const ScenarioOverrides& overrides = {});

// Robot preset files are read by the shared loader (loader/RobotLoader.hpp).
using loader::load_robot_preset;

// Default robots directory: $CARRIL_ROBOTS_DIR, else the source tree's config/robots.
std::string default_robots_dir();

// Named colours: white, black, red, green, blue, yellow (loader/MissionLoader.hpp).
using loader::color_from_name;

}  // namespace carril::sim
