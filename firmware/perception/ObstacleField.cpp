#include "firmware/perception/ObstacleField.hpp"

#include <cmath>

namespace carril::fw {

void ObstacleField::update(const hal::LaserScan& scan, const Pose2& odom) {
  pts_.clear();
  const double c = std::cos(myaw_), s = std::sin(myaw_);
  const int n = beams_.update(scan);
  const PoseFrame frame(odom);
  for (int i = 0; i < n; ++i) {
    float r = scan.ranges_m[std::size_t(i)];
    // -inf is something closer than the scanner can measure (REP 117): an obstacle at range_min.
    if (std::isinf(r) && r < 0.0F) r = scan.range_min_m > 0.0F ? scan.range_min_m : 0.01F;
    // isfinite first: comparing a NaN would raise FE_INVALID.
    if (!std::isfinite(r) || r <= 0.0F || r < scan.range_min_m || r > scan.range_max_m) {
      ++invalid_beams_;
      continue;
    }
    const double sx = double(r) * beams_.cos(i);
    const double sy = double(r) * beams_.sin(i);
    const Vec2 robot(mx_ + c * sx - s * sy, my_ + s * sx + c * sy);
    pts_.push_back(frame.to_world(robot));
  }
  valid_ = true;
}

double ObstacleField::ahead_m(const Pose2& odom, double margin_m, double max_m) const {
  double best = max_m;
  const double half_w = fp_.half_width_m + margin_m;
  const PoseFrame frame(odom);
  for (const Vec2& w : pts_) {
    const Vec2 p = frame.to_robot(w);
    if (p.x() > fp_.half_length_m && std::fabs(p.y()) <= half_w) {
      const double d = p.x() - fp_.half_length_m;
      if (d < best) best = d;
    }
  }
  return best;
}

double ObstacleField::clearance_m(const Pose2& odom) const {
  double best = 1e9;
  const PoseFrame frame(odom);
  for (const Vec2& w : pts_) {
    const Vec2 p = frame.to_robot(w);
    const double dx = std::fmax(std::fabs(p.x()) - fp_.half_length_m, 0.0);
    const double dy = std::fmax(std::fabs(p.y()) - fp_.half_width_m, 0.0);
    const double d = std::sqrt(dx * dx + dy * dy);
    if (d < best) best = d;
  }
  return best;
}

}  // namespace carril::fw
