#pragma once
// Shared fixtures for the scenario loader tests: a complete valid file and helpers that edit it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim::test {

inline const std::string kPath = "scenarios/test_scn.yaml";

// Every section, with values that differ from the defaults so parsing is visible.
inline const std::string kFullYaml = R"(name: corners-1_b
description: test scenario
duration_s: 240
seed: 7
floor: {color: [90, 91, 92]}
robot:
  preset: campero
  start: {x: 1.0, y: -2.0, yaw_deg: 90}
  camera: {noise_std: 4.0}
  lidar: {beams: 271}
  limits: {max_speed_mps: 1.2}
mission:
  type: follow_line
  strategy: line_priority
  line_color: white
  end_color: [0, 0, 255]
  speed_mps: 0.8
lines:
  - {color: white, width_m: 0.05, points: [[0, 0], [6, 0], [6, 4]]}
  - {color: [255, 0, 0], width_m: 0.04, arc: {center: [1, 2], radius_m: 3.0, start_deg: -90, end_deg: 270}}
  - {color: white, width_m: 0.06, points: [[6, 4], [0, 4]]}
marks:
  - {color: yellow, x: 6, y: 4.3, radius_m: 0.2}
obstacles:
  - {shape: box, x: 3, y: 0.5, yaw_deg: 30, size_m: [1.0, 2.0]}
  - {shape: cylinder, x: 6, y: 2, radius_m: 0.5}
walls:
  - {points: [[-2, -3], [10, -3], [10, 8]], thickness_m: 0.2}
terrain:
  - {type: ramp, x: 2, y: 5, yaw_deg: 45, length_m: 2.0, width_m: 1.5, angle_deg: 5}
  - {type: step, x: 6, y: 8, length_m: 2.5, width_m: 1.25, height_m: 0.2}
expect:
  end_reached: true
  max_collisions: 0
  max_cross_track_rms_m: 0.05
  min_progress: 1.0
  min_laps: 1
)";

// Smallest valid file: only the required keys.
inline const std::string kMinimalYaml = R"(name: minimal
duration_s: 10
robot: {preset: pioneer3at}
mission: {type: follow_line, strategy: pid, line_color: white}
lines:
  - {color: white, points: [[0, 0], [1, 0]]}
)";

inline std::string robots_dir() {
  const char* env = std::getenv("CARRIL_ROBOTS_DIR");
  return env != nullptr && env[0] != '\0' ? std::string(env)
                                          : std::string(CARRIL_SOURCE_DIR "/config/robots");
}

inline LoadResult load(const std::string& yaml) {
  return load_scenario_text(yaml, kPath, robots_dir());
}

// `text` with the first occurrence of `from` (which must exist) replaced by `to`.
inline std::string edit(const std::string& text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos == std::string::npos) return text;
  std::string out = text;
  out.replace(pos, from.size(), to);
  return out;
}

// 1-based line of the first occurrence of `needle` in `text`.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  int line = 1;
  for (std::size_t i = 0; i < pos && i < text.size(); ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

// A load failed with one message that starts with the file path and contains every fragment.
inline ::testing::AssertionResult fails_with(const LoadResult& r,
                                             std::initializer_list<std::string> fragments) {
  if (r.ok) return ::testing::AssertionFailure() << "loaded, expected an error";
  if (r.error.rfind(kPath + ":", 0) != 0) {
    return ::testing::AssertionFailure() << "message does not start with the path: " << r.error;
  }
  if (r.error.find('\n') != std::string::npos) {
    return ::testing::AssertionFailure() << "message spans lines: " << r.error;
  }
  for (const auto& f : fragments) {
    if (r.error.find(f) == std::string::npos) {
      return ::testing::AssertionFailure() << "message lacks '" << f << "': " << r.error;
    }
  }
  return ::testing::AssertionSuccess() << r.error;
}

// Loading `yaml` fails that way.
inline ::testing::AssertionResult fails_with(const std::string& yaml,
                                             std::initializer_list<std::string> fragments) {
  return fails_with(load(yaml), fragments);
}

}  // namespace carril::sim::test
