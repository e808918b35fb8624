#include "firmware/msg/ObstacleField.hpp"

#include <cmath>

namespace carril::fw {

void ObstacleField::update(const hal::LaserScan& scan, const Pose2& odom) {
  if (remember_m_ > 0.0) remember(scan, odom);
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
    moving_[pts_.size()] = 0;
    pts_.push_back(frame.to_world(robot));
  }
  // The field of view, for sees(): from the first beam to the last, whichever way the scan turns.
  const double a0 = double(scan.angle_min_rad);
  const double a1 = a0 + double(scan.angle_increment_rad) * (n > 0 ? n - 1 : 0);
  if (n > 1 && std::isfinite(a0) && std::isfinite(a1)) {
    fov_min_rad_ = std::fmin(a0, a1);
    fov_max_rad_ = std::fmax(a0, a1);
    range_max_m_ = std::isfinite(scan.range_max_m) ? double(scan.range_max_m) : 0.0;
  } else {
    fov_min_rad_ = 0.0;
    fov_max_rad_ = -1.0;
  }
  valid_ = true;
}

std::size_t ObstacleField::moving_count() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < pts_.size(); ++i) n += moving_[i];
  return n;
}

bool ObstacleField::sees(const Vec2& p) const {
  if (!(fov_max_rad_ >= fov_min_rad_)) return false;
  const double dx = p.x() - mx_, dy = p.y() - my_;
  if (dx * dx + dy * dy > range_max_m_ * range_max_m_) return false;
  // The bearing relative to the mount, unwrapped into the field of view when it can be.
  double a = wrap_angle(std::atan2(dy, dx) - myaw_);
  if (a < fov_min_rad_) a += 2.0 * kPi;
  if (a > fov_max_rad_) a -= 2.0 * kPi;
  return a >= fov_min_rad_ && a <= fov_max_rad_;
}

double ObstacleField::corridor_m(const Pose2& odom, double margin_m, double max_m, double dir,
                                 bool remembered, bool static_only) const {
  double best = max_m;
  const double half_w = fp_.half_width_m + margin_m;
  const PoseFrame frame(odom);
  const auto see = [&](const Vec2& w) {
    const Vec2 p = frame.to_robot(w);
    const double along = dir * p.x();
    if (along > fp_.half_length_m && std::fabs(p.y()) <= half_w) {
      best = std::fmin(best, along - fp_.half_length_m);
    }
  };
  for (std::size_t i = 0; i < pts_.size(); ++i) {
    if (!static_only || moving_[i] == 0) see(pts_[i]);
  }
  if (remembered) {
    for (const Vec2& w : memory_) see(w);
  }
  return best;
}

double ObstacleField::ahead_m(const Pose2& odom, double margin_m, double max_m,
                              bool static_only) const {
  return corridor_m(odom, margin_m, max_m, 1.0, false, static_only);
}

double ObstacleField::behind_m(const Pose2& odom, double margin_m, double max_m) const {
  if (memory_full_) return 0.0;
  return corridor_m(odom, margin_m, max_m, -1.0, true);
}

double ObstacleField::from_body_m(const Vec2& p) const {
  const double dx = std::fmax(std::fabs(p.x()) - fp_.half_length_m, 0.0);
  const double dy = std::fmax(std::fabs(p.y()) - fp_.half_width_m, 0.0);
  return std::sqrt(dx * dx + dy * dy);
}

double ObstacleField::clearance_m(const Pose2& odom) const {
  double best = 1e9;
  const PoseFrame frame(odom);
  for (const Vec2& w : pts_) best = std::fmin(best, from_body_m(frame.to_robot(w)));
  return best;
}

double ObstacleField::clearance_all_round_m(const Pose2& odom) const {
  if (memory_full_) return 0.0;
  double best = clearance_m(odom);
  const PoseFrame frame(odom);
  for (const Vec2& w : memory_) best = std::fmin(best, from_body_m(frame.to_robot(w)));
  return best;
}

bool ObstacleField::seen_past(const hal::LaserScan& scan, const PoseFrame& lidar,
                              const Vec2& w) const {
  const double inc = double(scan.angle_increment_rad);
  const Vec2 p = lidar.to_robot(w);
  const double r = p.norm();
  // The beam nearest the point's bearing, counted from the first beam the way the scan turns.
  double a = wrap_angle(fast_atan2(p.y(), p.x()) - double(scan.angle_min_rad));
  if (inc > 0.0 && a < -0.5 * inc) a += 2.0 * kPi;
  if (inc < 0.0 && a > -0.5 * inc) a -= 2.0 * kPi;
  const double k = std::round(a / inc);
  if (!(k >= 0.0 && k < double(scan.count))) return false;  // outside the field of view
  const float range = scan.ranges_m[std::size_t(k)];
  if (std::isnan(range)) return false;                                          // says nothing
  if (std::isinf(range)) return range > 0.0F && r <= double(scan.range_max_m);  // free to max
  // A return at the point or beyond it: the beam passed it (a nearer one hides it, so it stays).
  return double(range) >= r - 0.05;
}

void ObstacleField::remember(const hal::LaserScan& scan, const Pose2& odom) {
  const double reach = fp_.circumscribed_m() + remember_m_;
  const PoseFrame body(odom);
  const Vec2 mount = body.to_world(Vec2(mx_, my_));
  const PoseFrame lidar(Pose2{mount.x(), mount.y(), wrap_angle(odom.yaw + myaw_)});
  const double reach2 = reach * reach;
  // A scan whose beams cannot be placed looks past nothing (checked once, not per return).
  const double inc = double(scan.angle_increment_rad);
  const bool placed =
      scan.count > 0 && std::isfinite(inc) && inc != 0.0 && std::isfinite(scan.angle_min_rad);
  const auto keep = [&](const Vec2& w) {
    const Vec2 p = body.to_robot(w);
    if (p.squaredNorm() > reach2) return false;
    if (std::fabs(p.x()) < fp_.half_length_m && std::fabs(p.y()) < fp_.half_width_m) {
      return false;  // the body stands there now: whatever it was has gone
    }
    return !(placed && seen_past(scan, lidar, w));
  };
  std::size_t n = 0;
  for (const Vec2& w : memory_) {
    if (keep(w)) memory_[n++] = w;
  }
  memory_.truncate(n);
  // The last scan's points join (they are about to be replaced), thinned along the scan.
  bool have_last = false;
  Vec2 last(0.0, 0.0);
  for (const Vec2& w : pts_) {
    if (have_last && (w - last).norm() < kMemorySpacingM) continue;
    if (!keep(w)) continue;
    if (!memory_.try_push_back(w)) {
      memory_full_ = true;  // what it cannot hold it cannot vouch for: no turn is cleared
      return;
    }
    have_last = true;
    last = w;
  }
  memory_full_ = false;
}

}  // namespace carril::fw
