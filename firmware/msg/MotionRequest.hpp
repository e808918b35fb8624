#pragma once
// What a mission asks the drives for (published by the mission runner, consumed by MotionOutput).
#include "firmware/core/Geometry.hpp"

namespace carril::fw {

struct MotionRequest {
  Twist twist;           // body twist [m/s, m/s, rad/s]
  bool guarded = false;  // driving along its path: stop it for an obstacle ahead
};

}  // namespace carril::fw
