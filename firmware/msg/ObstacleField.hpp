#pragma once
// The latest lidar scan as points in the odometry frame (in beam order), and the questions the
// behaviours ask of it. Distances are measured from the robot's footprint, not from the sensor,
// so a lidar mounted off-centre (campero's front-right corner) needs no hand-shaped zones.
#include <array>
#include <cmath>
#include <cstdint>

#include "firmware/core/BeamDirections.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct Footprint {
  double half_length_m = 0.25, half_width_m = 0.25;
  // The circumscribed circle's radius: what a turn in place sweeps [m].
  double circumscribed_m() const { return std::hypot(half_length_m, half_width_m); }
  // How far that circle reaches beyond the nearer sides [m].
  double turn_sweep_m() const {
    return circumscribed_m() - (half_length_m < half_width_m ? half_length_m : half_width_m);
  }
};

class ObstacleField {
 public:
  // `remember_m`: keep the returns that leave the scanner's view (remembered(), below) while they
  // are within this distance of the footprint's circumscribed circle (0: keep none) [m]. Only a
  // user of clearance_all_round_m needs them, and they cost a bearing per nearby return per scan.
  ObstacleField(const Footprint& fp, double mount_x, double mount_y, double mount_yaw,
                double remember_m = 0.0)
      : fp_(fp), mx_(mount_x), my_(mount_y), myaw_(mount_yaw), remember_m_(remember_m) {}

  // Converts a scan taken at odometry pose `odom`. NaN, +inf, zero and out-of-limit ranges are
  // skipped (and counted): no return is not an obstacle. -inf (too close to measure) is an
  // obstacle at range_min.
  void update(const hal::LaserScan& scan, const Pose2& odom);
  bool valid() const { return valid_; }
  std::uint64_t invalid_beams() const { return invalid_beams_; }
  const StaticVector<Vec2, hal::kMaxScanBeams>& points() const { return pts_; }
  // Point i lies where an older scan saw free space (MovingReturns): something moving, not a
  // wall revealed by the robot's own motion.
  bool moving(std::size_t i) const { return moving_[i] != 0; }
  void set_moving(std::size_t i, bool m) { moving_[i] = m ? 1 : 0; }
  std::size_t moving_count() const;
  // The lidar sees a robot-frame point: its bearing from the mount lies within the last scan's
  // field of view and it is nearer than the scan's range_max. False before the first scan.
  bool sees(const Vec2& robot_point) const;
  // The lidar's mount in the robot frame [m, m, rad].
  double mount_x() const { return mx_; }
  double mount_y() const { return my_; }
  double mount_yaw() const { return myaw_; }

  // Free distance ahead of the front bumper inside a corridor as wide as the robot plus
  // `margin_m` each side, up to `max_m` (returns max_m when clear) [m]. With `static_only`,
  // returns marked moving are left out.
  double ahead_m(const Pose2& odom, double margin_m, double max_m, bool static_only = false) const;
  // The same behind the rear bumper, over this scan's points and the remembered ones (a 180 deg
  // lidar sees nothing behind); 0 when the memory overflowed [m].
  double behind_m(const Pose2& odom, double margin_m, double max_m) const;
  // Smallest distance from any point to the footprint rectangle at `odom` [m].
  double clearance_m(const Pose2& odom) const;
  // The same over this scan's points and the remembered ones (below): what a turn in place can
  // meet all round, blind sectors included; 0 when the memory overflowed [m].
  double clearance_all_round_m(const Pose2& odom) const;

  // Returns of earlier scans still near the robot (within remember_m of the footprint's
  // circumscribed circle) that no later beam has looked past: what lies in the scanner's blind
  // sector (behind a 180 deg lidar, say) after it was last seen. Odometry frame, so a localisation
  // jump does not move them; thinned to one point every kMemorySpacingM along each scan.
  static constexpr std::size_t kMaxRemembered = 1024;
  static constexpr double kMemorySpacingM = 0.02;  // [m]
  const StaticVector<Vec2, kMaxRemembered>& remembered() const { return memory_; }
  bool memory_overflowed() const { return memory_full_; }
  const Footprint& footprint() const { return fp_; }

 private:
  Footprint fp_;
  double mx_, my_, myaw_;
  double remember_m_;
  bool valid_ = false;
  std::uint64_t invalid_beams_ = 0;
  // From robot-frame point p to the footprint rectangle (0 inside it) [m].
  double from_body_m(const Vec2& p) const;
  // Free distance from the front (dir +1) or rear (dir -1) bumper inside the corridor of
  // ahead_m, over this scan's points and, with `remembered`, the remembered ones [m].
  double corridor_m(const Pose2& odom, double margin_m, double max_m, double dir, bool remembered,
                    bool static_only = false) const;
  // Keeps the remembered points and the last scan's (pts_, before it is replaced) that are near
  // the robot at `odom`, outside its body, and not looked past by a beam of `scan`.
  void remember(const hal::LaserScan& scan, const Pose2& odom);
  // Whether a beam of `scan` (taken from lidar pose `lidar`, its beams' geometry finite and its
  // increment non-zero) looked at or past odometry point w.
  bool seen_past(const hal::LaserScan& scan, const PoseFrame& lidar, const Vec2& w) const;

  StaticVector<Vec2, hal::kMaxScanBeams> pts_;
  std::array<std::uint8_t, hal::kMaxScanBeams> moving_{};
  double fov_min_rad_ = 0.0, fov_max_rad_ = -1.0;  // last scan's beams, sensor frame [rad]
  double range_max_m_ = 0.0;                       // [m]
  StaticVector<Vec2, kMaxRemembered> memory_;
  bool memory_full_ = false;
  BeamDirections beams_;  // no trigonometry per beam per scan
};

}  // namespace carril::fw
