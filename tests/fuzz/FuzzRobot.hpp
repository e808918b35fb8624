#pragma once
// The robot the mission and controller targets read their files for: config/robots/campero.yaml
// (mecanum, lidar, camera: every section of those files applies to it).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "loader/RobotLoader.hpp"

namespace carril::fuzz {

inline const loader::RobotSpec& campero() {
  static const loader::RobotSpec robot = [] {
    loader::RobotSpec r;
    std::string error;
    if (!loader::load_robot_preset(CARRIL_SOURCE_DIR "/config/robots/campero.yaml", r, error)) {
      std::fprintf(stderr, "carril fuzz: %s\n", error.c_str());
      std::abort();
    }
    return r;
  }();
  return robot;
}

}  // namespace carril::fuzz
