#pragma once
// Messages `odometry` (WheelOdometry, odometry frame) and `pose` (Localisation, map frame).
#include <cstdint>

#include "firmware/core/Geometry.hpp"

namespace carril::fw {

// The robot in its frame: the odometry frame (origin where the firmware started), or the map's.
struct OdometryMsg {
  Pose2 pose;   // [m, m, rad]
  Twist twist;  // measured from wheel speeds [m/s, m/s, rad/s]
  // The pose can be trusted in its frame (always for odometry; on a map, once localisation has
  // converged and while it stays so).
  bool localised = true;
  // Times the localisation was regained after being lost: the pose may have jumped, so what was
  // built from the old one (costmap marks, a plan) is suspect [count].
  std::uint32_t relocalisations = 0;
};

}  // namespace carril::fw
