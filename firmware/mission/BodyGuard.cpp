#include "firmware/mission/BodyGuard.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {

constexpr double kStepM = 0.02;    // arc samples: at most this far apart [m]
constexpr double kStepRad = 0.05;  // and at most this much turn apart [rad]

}  // namespace

BodyGuard::BodyGuard(double half_length_m, double half_width_m, double pad_m, double radius_m)
    : hl_(half_length_m), hw_(half_width_m), pad_(pad_m), radius_(radius_m) {}

double BodyGuard::swept_radius() const {
  return std::hypot(hl_, hw_) + pad_ + half_cell_;
}

void BodyGuard::gather(const Pose2& pose, const RollingGrid<std::uint8_t>& grid) {
  cells_.clear();
  crowded_ = false;
  if (!grid.ready()) return;
  half_cell_ = 0.5 * grid.resolution();
  // Nowhere known: nothing may move.
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw)) {
    crowded_ = true;
    return;
  }
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const int x0 = grid.cell_of(pose.x - radius_), x1 = grid.cell_of(pose.x + radius_);
  const int y0 = grid.cell_of(pose.y - radius_), y1 = grid.cell_of(pose.y + radius_);
  const double r2 = radius_ * radius_;
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      if (!grid.contains(cx, cy) || grid.at(cx, cy) != cost::kLethal) continue;
      const double dx = grid.center_of(cx) - pose.x, dy = grid.center_of(cy) - pose.y;
      if (dx * dx + dy * dy > r2) continue;
      if (!cells_.try_push_back(Cell{float(c * dx + s * dy), float(-s * dx + c * dy)})) {
        crowded_ = true;
        return;
      }
    }
  }
}

void BodyGuard::add_points(const Vec2* points, std::size_t count, const Pose2& pose) {
  if (crowded_) return;
  const PoseFrame frame(pose);
  const double r2 = radius_ * radius_;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec2 p = frame.to_robot(points[i]);
    if (p.squaredNorm() > r2 || (std::fabs(p.x()) <= hl_ && std::fabs(p.y()) <= hw_)) continue;
    if (!cells_.try_push_back(Cell{float(p.x()), float(p.y())})) {
      crowded_ = true;
      return;
    }
  }
}

BodyGuard::Nearest BodyGuard::nearest() const {
  return nearest_around(Vec2(0.0, 0.0), 1e150);
}

BodyGuard::Nearest BodyGuard::nearest_around(const Vec2& p, double within_m) const {
  Nearest n;
  double best = 1e300;
  const double w2 = within_m * within_m;
  for (const Cell& k : cells_) {
    const double x = double(k.x), y = double(k.y);
    if ((x - p.x()) * (x - p.x()) + (y - p.y()) * (y - p.y()) > w2) continue;
    const double d2 = x * x + y * y;
    if (d2 < best) {
      best = d2;
      n.p = Vec2(x, y);
    }
  }
  if (best < 1e300) {
    n.found = true;
    n.d_m = std::sqrt(best);
  }
  return n;
}

double BodyGuard::distance_to(const Vec2& p) const {
  double best = 1e300;
  for (const Cell& k : cells_) {
    const double dx = double(k.x) - p.x(), dy = double(k.y) - p.y();
    const double d2 = dx * dx + dy * dy;
    // A comparison, not fmin: aarch64 GCC 12's vectoriser fails on an fmin reduction here
    // (internal compiler error in vect_transform_reduction).
    if (d2 < best) best = d2;
  }
  return best < 1e300 ? std::sqrt(best) : best;
}

BodyGuard::Corridor BodyGuard::corridor(const Vec2& dir, double half_width_m, double length_m,
                                        double depth_m) const {
  Corridor c;
  c.first_m = crowded_ ? 0.0 : length_m;
  if (crowded_) return c;
  for (const Cell& k : cells_) {
    const double u = dir.x() * double(k.x) + dir.y() * double(k.y);
    const double w = -dir.y() * double(k.x) + dir.x() * double(k.y);
    if (u > 0.0 && u < c.first_m && std::fabs(w) <= half_width_m) {
      c.first_m = u;
      c.first_p = Vec2(double(k.x), double(k.y));
    }
  }
  if (c.first_m >= length_m) return c;
  double sum = 0.0;
  for (const Cell& k : cells_) {
    const double u = dir.x() * double(k.x) + dir.y() * double(k.y);
    const double w = -dir.y() * double(k.x) + dir.x() * double(k.y);
    if (u >= c.first_m && u <= c.first_m + depth_m && std::fabs(w) <= half_width_m) {
      sum += w;
      ++c.cells;
    }
  }
  c.mean_side_m = sum / double(c.cells);
  return c;
}

bool BodyGuard::inside(const Cell& k, double x, double y, double yaw, double grow) const {
  const double dx = double(k.x) - x, dy = double(k.y) - y;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
  return std::fabs(lx) <= hl_ + grow && std::fabs(ly) <= hw_ + grow;
}

bool BodyGuard::hits(double x, double y, double yaw, double x0) const {
  const double padded = pad_ + half_cell_;
  for (const Cell& k : cells_) {
    const bool in_pad_now = inside(k, x0, 0.0, 0.0, padded);
    if (inside(k, x, y, yaw, in_pad_now ? half_cell_ : padded)) return true;
  }
  return false;
}

double BodyGuard::free_length(double k, bool reverse, double max_m) const {
  if (crowded_) return 0.0;
  if (!(max_m > 0.0)) return 0.0;
  // Nothing within reach of the swept body: all clear without sampling.
  const Nearest n = nearest();
  if (!n.found || n.d_m > swept_radius() + max_m) return max_m;
  const double step = std::fabs(k) > 1e-9 ? std::min(kStepM, kStepRad / std::fabs(k)) : kStepM;
  const double dir = reverse ? -1.0 : 1.0;
  for (double s = step;; s += step) {
    const double at = std::min(s, max_m);
    const double a = dir * at;  // signed arc length
    double x = a, y = 0.0, yaw = 0.0;
    if (std::fabs(k) > 1e-9) {
      yaw = k * a;
      x = std::sin(yaw) / k;
      y = (1.0 - std::cos(yaw)) / k;
    }
    if (hits(x, y, yaw)) return std::max(0.0, at - step);
    if (at >= max_m) return max_m;
  }
}

bool BodyGuard::rotation_clear(double angle_rad, double shift_m) const {
  if (crowded_) return false;
  const Nearest n = nearest_around(Vec2(shift_m, 0.0), swept_radius());
  if (!n.found) return true;  // the swept circle is clear
  const double span = std::fabs(angle_rad);
  const double dir = angle_rad < 0.0 ? -1.0 : 1.0;
  for (double a = std::min(kStepRad, span);; a = std::min(a + kStepRad, span)) {
    if (hits(shift_m, 0.0, dir * a, shift_m)) return false;
    if (a >= span) return true;
  }
}

double BodyGuard::escape_shift(double angle_rad, double step_m, double max_m,
                               double min_free_m) const {
  const int steps = int(std::floor(max_m / step_m + 1e-9));
  for (int step = 1; step <= steps; ++step) {
    const double d = step * step_m;
    for (const double dir : {-1.0, 1.0}) {
      const double need = std::fmax(d, min_free_m);
      if (rotation_clear(angle_rad, dir * d) && free_length(0.0, dir < 0.0, need) >= need) {
        return dir * d;
      }
    }
  }
  return 0.0;
}

}  // namespace carril::fw
