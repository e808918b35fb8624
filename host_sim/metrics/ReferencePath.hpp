#pragma once
// The mission's reference path: the concatenation, in file order, of the tape lines whose colour
// is the mission's line colour. Used to score a run (cross-track, progress, laps).
#include <vector>

#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

struct PathPoint {
  double s_m = 0.0;     // arc length along the path at the projection [m]
  double dist_m = 0.0;  // distance from the query point to the path [m]
  Vec2 p;               // the projection
};

class ReferencePath {
 public:
  ReferencePath() = default;
  explicit ReferencePath(const Scenario& scenario);

  bool empty() const { return pts_.size() < 2; }
  double length_m() const { return cum_.empty() ? 0.0 : cum_.back(); }
  // Closed when the last point is within 1 cm of the first (a loop, which laps count).
  bool closed() const { return closed_; }
  const std::vector<Vec2>& points() const { return pts_; }

  // Nearest point over the whole path. Const but not for two threads at once: it keeps the
  // segment it found as the next call's first try.
  PathPoint nearest(Vec2 q) const;
  // Nearest point among arc lengths in [s_from, s_to] (wrapping round a closed path).
  PathPoint nearest_in(Vec2 q, double s_from, double s_to) const;
  // Point at arc length s (wrapped on a closed path, clamped on an open one).
  Vec2 at(double s) const;

 private:
  std::vector<Vec2> pts_;
  std::vector<double> cum_;  // cumulative arc length at each point
  bool closed_ = false;
  // Per segment, its midpoint and half its length: a segment whose circle is farther than the
  // best so far is passed over before its projection (a division). Only where every point lies
  // within kScreenRangeM of the origin (rounding then stays far below the screen's slack).
  std::vector<Vec2> mid_;
  std::vector<double> half_;
  bool screen_ = false;
  // The segment nearest() found last: tried first next time, so the squared-distance screen
  // passes few of the others (consecutive queries are usually near each other).
  mutable std::size_t hint_ = 0;
};

}  // namespace carril::sim
