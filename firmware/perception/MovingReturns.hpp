#pragma once
// Which lidar returns belong to something moving: a return that lies where an older scan's beams
// saw free space (they reached past it), with no older return within the margin of it, is
// something that moved in, not a wall the robot's own motion brought into view (a newly seen
// static surface was hidden or out of view before, never seen through; an edge seen from a new
// place has its older returns beside it). Every return of a cluster (consecutive returns closer
// than kClusterGapM) holding such returns is marked, so a walking person counts as moving as a
// whole, not only its leading edge. The protective fields give moving returns the approach speed of
// a person (ISO 13855's K); static ones are only what they are.
//
// Sized at construction: the older scans live in a fixed ring; classify() never allocates.
#include <array>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct MovingReturnsConfig {
  // Compare each scan with the one about this much older: long enough that a person walking at
  // 0.4 m/s has moved past margin_m, short enough that little else has changed [s].
  double history_s = 0.25;
  // A return must lie at least this far inside the space the older beams saw free: more than the
  // lidar's range noise and the odometry's drift over history_s [m].
  double margin_m = 0.08;
  double margin_per_m = 0.01;  // plus this much per metre of range (beam divergence) [m/m]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<MovingReturnsConfig>> params();
  Status validate() const;
  bool operator==(const MovingReturnsConfig&) const = default;
};

class MovingReturns {
 public:
  static constexpr int kMaxHistory = 16;       // older scans kept at most
  static constexpr double kClusterGapM = 0.2;  // returns closer than this are one object [m]
  static constexpr int kMinSeen = 2;     // a cluster moves when this many of its returns were seen
                                         // through (a lone one is more likely an edge's parallax)
  static constexpr int kMaxWindow = 64;  // older beams each side searched for the same surface

  // `rate_hz`: the lidar's scan rate, which sets how many scans back history_s is.
  MovingReturns(const MovingReturnsConfig& cfg, double rate_hz);

  // Marks the moving returns of `field`, just updated from `scan` taken at odometry pose `odom`,
  // then keeps `scan` for the scans to come.
  void classify(const hal::LaserScan& scan, const Pose2& odom, ObstacleField& field);
  int depth() const { return depth_; }  // scans back the comparison looks

 private:
  struct Past {
    bool filled = false;
    Pose2 lidar;  // the lidar's pose, odometry frame
    float angle_min = 0.0F, increment = 0.0F, range_min = 0.0F, range_max = 0.0F;
    std::uint16_t count = 0;
    std::array<float, hal::kMaxScanBeams> ranges{};
  };
  // Older beams reached past odometry point w (it was free there) and no older return lies
  // within the margin of it.
  bool seen_through(const Past& past, const PoseFrame& lidar, const Vec2& w) const;

  MovingReturnsConfig cfg_;
  int depth_;
  int next_ = 0;  // the ring slot the next scan goes to
  std::array<Past, kMaxHistory> ring_{};
};

}  // namespace carril::fw
