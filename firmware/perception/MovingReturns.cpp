#include "firmware/perception/MovingReturns.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

std::span<const Param<MovingReturnsConfig>> MovingReturnsConfig::params() {
  using C = MovingReturnsConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, history_s, "s", 0.0, 2.0,
                   "each scan is compared with the one this much older"),
      CARRIL_PARAM(C, margin_m, "m", 0.0, 1.0,
                   "a return this far inside space an older scan saw free is moving"),
      CARRIL_PARAM(C, margin_per_m, "m/m", 0.0, 0.2, "plus this per metre of range"),
  };
  return kParams;
}

Status MovingReturnsConfig::validate() const {
  return Checks("lidar.moving").params(*this, params()).result();
}

MovingReturns::MovingReturns(const MovingReturnsConfig& cfg, double rate_hz)
    : cfg_(cfg),
      depth_(
          std::clamp(static_cast<int>(std::lround(cfg.history_s * rate_hz)), 1, kMaxHistory - 1)) {}

bool MovingReturns::seen_through(const Past& past, const PoseFrame& lidar, const Vec2& w) const {
  const double inc = double(past.increment);
  const Vec2 p = lidar.to_robot(w);
  const double r = p.norm();
  double a = wrap_angle(fast_atan2(p.y(), p.x()) - double(past.angle_min));
  if (inc > 0.0 && a < -0.5 * inc) a += 2.0 * kPi;
  if (inc < 0.0 && a > -0.5 * inc) a -= 2.0 * kPi;
  const double kf = std::round(a / inc);
  if (!(kf >= 0.0 && kf < double(past.count))) return false;  // it did not look there
  const int k = static_cast<int>(kf);
  const double need = r + cfg_.margin_m + cfg_.margin_per_m * r;
  // The beam and both its neighbours must have reached past: a surface seen at a grazing angle,
  // or an edge, puts one of them short of it.
  int looked = 0;
  for (int j = std::max(0, k - 1); j <= std::min(int(past.count) - 1, k + 1); ++j) {
    const float range = past.ranges[std::size_t(j)];
    if (std::isnan(range)) return false;  // says nothing
    if (std::isinf(range)) {
      // No return says the beam went through to range_max: only a point well short of it
      // (by the margin, as for a finite return) was seen through, not one near the range's end
      // where the range noise alone decides whether a wall returned.
      if (range < 0.0F || need > double(past.range_max)) return false;
    } else if (range <= 0.0F || range < past.range_min || range > past.range_max ||
               double(range) < need) {
      return false;  // an invalid range says nothing; a return short of the point hides it
    }
    ++looked;
  }
  if (looked < 2) return false;
  // Seen through, but an older return within the margin of it is the same surface seen from
  // elsewhere (an edge the robot's own motion moved across the beams), not something new.
  const double margin = cfg_.margin_m + cfg_.margin_per_m * r;
  const double window = std::atan2(margin, std::fmax(r, 1e-3)) / std::fabs(inc);
  const int half = std::min(kMaxWindow, static_cast<int>(window) + 1);
  const Vec2 origin(lidar.pose.x, lidar.pose.y);
  const double m2 = margin * margin;
  for (int j = std::max(0, k - half); j <= std::min(int(past.count) - 1, k + half); ++j) {
    const float range = past.ranges[std::size_t(j)];
    if (!std::isfinite(range) || range < past.range_min || range > past.range_max) continue;
    const double beam = lidar.pose.yaw + double(past.angle_min) + j * inc;
    const Vec2 q = origin + double(range) * Vec2(std::cos(beam), std::sin(beam));
    if ((q - w).squaredNorm() < m2) return false;
  }
  return true;
}

void MovingReturns::classify(const hal::LaserScan& scan, const Pose2& odom, ObstacleField& field) {
  const int n = std::min<int>(scan.count, hal::kMaxScanBeams);
  const Past& older = ring_[std::size_t((next_ - depth_ + kMaxHistory) % kMaxHistory)];
  const auto& pts = field.points();
  const bool placed = older.filled && older.count > 0 && std::isfinite(older.increment) &&
                      older.increment != 0.0F && std::isfinite(older.angle_min);
  if (placed) {
    const PoseFrame lidar(older.lidar);
    // Mark the returns seen through, then spread the marks over their clusters (points are in
    // beam order, so a cluster is a run of neighbours).
    for (std::size_t i = 0; i < pts.size(); ++i)
      field.set_moving(i, seen_through(older, lidar, pts[i]));
    std::size_t start = 0;
    for (std::size_t i = 1; i <= pts.size(); ++i) {
      if (i < pts.size() && (pts[i] - pts[i - 1]).norm() < kClusterGapM) continue;
      int seen = 0;
      for (std::size_t j = start; j < i && seen < kMinSeen; ++j) seen += field.moving(j) ? 1 : 0;
      for (std::size_t j = start; j < i; ++j) field.set_moving(j, seen >= kMinSeen);
      start = i;
    }
  }
  // Keep this scan, with the lidar's pose it was taken from.
  Past& slot = ring_[std::size_t(next_)];
  const PoseFrame body(odom);
  const Vec2 mount = body.to_world(Vec2(field.mount_x(), field.mount_y()));
  slot.lidar = Pose2{mount.x(), mount.y(), wrap_angle(odom.yaw + field.mount_yaw())};
  slot.angle_min = scan.angle_min_rad;
  slot.increment = scan.angle_increment_rad;
  slot.range_min = scan.range_min_m;
  slot.range_max = scan.range_max_m;
  slot.count = static_cast<std::uint16_t>(n);
  std::copy(scan.ranges_m.begin(), scan.ranges_m.begin() + n, slot.ranges.begin());
  slot.filled = true;
  next_ = (next_ + 1) % kMaxHistory;
}

}  // namespace carril::fw
