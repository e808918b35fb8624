#pragma once
// The latest lidar scan as points in the odometry frame (in beam order), and the questions the
// behaviours ask of it. Distances are measured from the robot's footprint, not from the sensor,
// so a lidar mounted off-centre (campero's front-right corner) needs no hand-shaped zones.
#include <array>
#include <cstdint>

#include "firmware/core/BeamDirections.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct Footprint {
  double half_length_m = 0.25, half_width_m = 0.25;
};

class ObstacleField {
 public:
  ObstacleField(const Footprint& fp, double mount_x, double mount_y, double mount_yaw)
      : fp_(fp), mx_(mount_x), my_(mount_y), myaw_(mount_yaw) {}

  // Converts a scan taken at odometry pose `odom`. NaN, +inf, zero and out-of-limit ranges are
  // skipped (and counted): no return is not an obstacle. -inf (too close to measure) is an
  // obstacle at range_min.
  void update(const hal::LaserScan& scan, const Pose2& odom);
  bool valid() const { return valid_; }
  std::uint64_t invalid_beams() const { return invalid_beams_; }
  const StaticVector<Vec2, hal::kMaxScanBeams>& points() const { return pts_; }

  // Free distance ahead of the front bumper inside a corridor as wide as the robot plus
  // `margin_m` each side, up to `max_m` (returns max_m when clear) [m].
  double ahead_m(const Pose2& odom, double margin_m, double max_m) const;
  // Smallest distance from any point to the footprint rectangle at `odom` [m].
  double clearance_m(const Pose2& odom) const;
  const Footprint& footprint() const { return fp_; }

 private:
  Footprint fp_;
  double mx_, my_, myaw_;
  bool valid_ = false;
  std::uint64_t invalid_beams_ = 0;
  StaticVector<Vec2, hal::kMaxScanBeams> pts_;
  BeamDirections beams_;  // no trigonometry per beam per scan
};

}  // namespace carril::fw
