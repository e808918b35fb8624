#pragma once
// The checks the path-following missions (goto, coverage's transits) each wrote for themselves:
// is the path ahead blocked, and have the emergency stops come too many in a row.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "firmware/core/Geometry.hpp"

namespace carril::fw {

// True when blocked(p) holds at a point of the path ahead: from the robot at `pose` along
// waypoints[from], waypoints[from + 1], ... for `lookahead_m` (each whole segment begun within
// it), sampled every `step_m` or finer. A point within `own_radius_m` of the robot never counts:
// it is the robot's own (inflated) cell, which it may stand in.
template <class Blocked>
bool path_blocked_ahead(const Pose2& pose, const Vec2* waypoints, std::size_t count,
                        std::size_t from, double lookahead_m, double step_m, double own_radius_m,
                        Blocked&& blocked) {
  const Vec2 robot(pose.x, pose.y);
  double left = lookahead_m;
  Vec2 a = robot;
  for (std::size_t i = from; i < count && left > 0.0; ++i) {
    const Vec2 b = waypoints[i];
    const double len = (b - a).norm();
    const int n = static_cast<int>(std::ceil(len / step_m));
    for (int k = 1; k <= n; ++k) {
      const Vec2 p = a + (b - a) * (double(k) / n);
      if (blocked(p) && (p - robot).norm() > own_radius_m) return true;
    }
    left -= len;
    a = b;
  }
  return false;
}

// The emergency stops of a mission that backs up and tries again: too many in a row (with no
// progress between them) and it gives its target up.
class StopStreak {
 public:
  // A stop at `here` [m]: true when it is the (max + 1)-th in a row. A stop farther than
  // `progress_m` from the one before starts a new streak (the robot got somewhere meanwhile).
  bool too_many(const Vec2& here, double progress_m, std::uint32_t max) {
    if (count_ > 0 && (here - last_).norm() > progress_m) count_ = 0;
    last_ = here;
    return ++count_ > max;
  }
  // Progress made (a goal reached, a new pose): the next stop starts a streak.
  void reset() { count_ = 0; }
  std::uint32_t count() const { return count_; }

 private:
  std::uint32_t count_ = 0;
  Vec2 last_{0.0, 0.0};
};

}  // namespace carril::fw
