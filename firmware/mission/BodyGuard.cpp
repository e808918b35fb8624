#include "firmware/mission/BodyGuard.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {

constexpr double kStepM = 0.02;    // arc samples: at most this far apart [m]
constexpr double kStepRad = 0.05;  // and at most this much turn apart [rad]
// With no_closer: how much nearer a cell already in the padding may come (sampling) [m], and
// how much more per metre the body travels: a path that grazes a wall it is already close to
// (within about 14 degrees of it) goes on, one that turns into it stops.
constexpr double kCloserM = 0.005;
constexpr double kGrazePerM = 0.25;
// With no_closer: the gap to a surface no motion closes below, grazing or not, tick after tick
// (the lidar's returns are good to a centimetre, the pad keeps 3) [m].
constexpr double kTouchM = 0.005;

}  // namespace

BodyGuard::BodyGuard(double half_length_m, double half_width_m, double pad_m, double radius_m)
    : hl_(half_length_m), hw_(half_width_m), pad_(pad_m), radius_(radius_m) {}

double BodyGuard::swept_radius() const {
  return (round_ ? std::min(hl_, hw_) : std::hypot(hl_, hw_)) + pad_ + half_cell_;
}

void BodyGuard::gather(const Pose2& pose, const RollingGrid<std::uint8_t>& grid) {
  cells_.clear();
  crowded_ = false;
  add_cells(pose, grid);
}

void BodyGuard::add_cells(const Pose2& pose, const RollingGrid<std::uint8_t>& grid) {
  if (crowded_ || !grid.ready()) return;
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
      if (!cells_.try_push_back(
              Cell{float(c * dx + s * dy), float(-s * dx + c * dy), float(half_cell_)})) {
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
    // A return inside the body is the robot's own; a round body's is its disc, not the square
    // round it (a wall beside its shoulder lies in the square's corner).
    const bool own = round_ ? p.norm() <= std::min(hl_, hw_)
                            : std::fabs(p.x()) <= hl_ && std::fabs(p.y()) <= hw_;
    if (p.squaredNorm() > r2 || own) continue;
    if (!cells_.try_push_back(
            Cell{float(p.x()), float(p.y()), exact_points_ ? 0.0F : float(half_cell_)})) {
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

double BodyGuard::gap(const Cell& k, double x, double y, double yaw) const {
  // How far outside the body the cell's reach is (0 or less: in it): a disc's radial gap, a
  // rectangle's larger gap along its axes (the grown-rectangle test's own measure).
  const double dx = double(k.x) - x, dy = double(k.y) - y;
  if (round_) return std::hypot(dx, dy) - std::min(hl_, hw_) - double(k.grow);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
  return std::fmax(std::fabs(lx) - hl_, std::fabs(ly) - hw_) - double(k.grow);
}

double BodyGuard::clearance_at(double x0, double y0) const {
  double best = 1e300;
  for (const Cell& k : cells_) best = std::fmin(best, gap(k, x0, y0, 0.0));
  return best;
}

bool BodyGuard::hits(double x, double y, double yaw, double x0, double y0, double travel,
                     double clear0) const {
  // Each cell's own reach (half a cell, or 0 for an exact point) on top of the padding; a cell
  // already inside the padding at (x0, y0) only stops the bare body grown by its reach, or, with
  // no_closer, any motion that brings it nearer the body than by grazing.
  const double c = std::cos(yaw), s = std::sin(yaw);  // worked out once, not once per cell
  const double r = std::min(hl_, hw_);
  for (const Cell& k : cells_) {
    const double kx = double(k.x), ky = double(k.y), g = double(k.grow);
    const double padded = pad_ + g;
    const double dx = kx - x, dy = ky - y;
    const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
    if (no_closer_) {
      const double now = gap(k, x0, y0, 0.0);
      const double then = gap(k, x, y, yaw);
      // What the cell may come to: the padding; but a robot already nearer something than the
      // padding (a wall it runs along) may bring others as near as that (the wall's next
      // returns), and what is in the padding may come nearer by grazing, never to the surface.
      if (now > pad_ && clear0 >= pad_) {
        if (then <= pad_) return true;
        continue;
      }
      // The touch floor holds however often a tick comes a little nearer: below it a cell may
      // only recede.
      const double soft = (now > pad_ ? clear0 : now) - kCloserM - kGrazePerM * travel;
      const double limit = std::fmin(std::fmax(soft, kTouchM), now);
      if (then < limit) return true;
      continue;
    }
    if (round_) {
      const double d0 = std::hypot(kx - x0, ky - y0), d = std::hypot(dx, dy);
      if (d <= r + (d0 <= r + padded ? g : padded)) return true;
      continue;
    }
    const bool in_pad_now =
        std::fabs(kx - x0) <= hl_ + padded && std::fabs(ky - y0) <= hw_ + padded;
    const double grow = in_pad_now ? g : padded;
    if (std::fabs(lx) <= hl_ + grow && std::fabs(ly) <= hw_ + grow) return true;
  }
  return false;
}

double BodyGuard::free_travel(const Twist& t, double max_m) const {
  if (crowded_) return 0.0;
  const double v = std::hypot(t.vx, t.vy);
  if (!(max_m > 0.0) || v < 1e-9) return 0.0;
  const Nearest n = nearest();
  if (!n.found || n.d_m > swept_radius() + max_m) return max_m;
  const double clear0 = no_closer_ ? clearance_at(0.0, 0.0) : 0.0;
  // Time along the path, sampled at most kStepM of travel and kStepRad of turn apart.
  const double w = t.wz;
  const double dt = std::min(kStepM / v, std::fabs(w) > 1e-9 ? kStepRad / std::fabs(w) : 1e9);
  // No further than a whole turn round the arc's centre: past it the path repeats.
  double t_end = max_m / v;
  if (std::fabs(w) > 1e-9) t_end = std::min(t_end, 2.0 * kPi / std::fabs(w));
  for (double tau = dt;; tau += dt) {
    const double at = std::min(tau, t_end);
    // The constant body twist integrated from the origin: a circular arc (or a line).
    double x = t.vx * at, y = t.vy * at;
    const double yaw = w * at;
    if (std::fabs(w) > 1e-9) {
      const double sn = std::sin(yaw), cs = std::cos(yaw);
      x = (t.vx * sn - t.vy * (1.0 - cs)) / w;
      y = (t.vx * (1.0 - cs) + t.vy * sn) / w;
    }
    if (hits(x, y, yaw, 0.0, 0.0, at * v, clear0)) return std::max(0.0, (at - dt) * v);
    if (at >= t_end) return max_m;  // the reach, or a whole loop, is clear
  }
}

double BodyGuard::free_length(double k, bool reverse, double max_m) const {
  if (crowded_) return 0.0;
  if (!(max_m > 0.0)) return 0.0;
  // Nothing within reach of the swept body: all clear without sampling.
  const Nearest n = nearest();
  if (!n.found || n.d_m > swept_radius() + max_m) return max_m;
  const double clear0 = no_closer_ ? clearance_at(0.0, 0.0) : 0.0;
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
    if (hits(x, y, yaw, 0.0, 0.0, at, clear0)) return std::max(0.0, at - step);
    if (at >= max_m) return max_m;
  }
}

bool BodyGuard::rotation_clear(double angle_rad, double shift_m) const {
  if (crowded_) return false;
  const Nearest n = nearest_around(Vec2(shift_m, 0.0), swept_radius());
  if (!n.found) return true;  // the swept circle is clear
  const double clear0 = no_closer_ ? clearance_at(shift_m, 0.0) : 0.0;
  const double span = std::fabs(angle_rad);
  const double dir = angle_rad < 0.0 ? -1.0 : 1.0;
  for (double a = std::min(kStepRad, span);; a = std::min(a + kStepRad, span)) {
    if (hits(shift_m, 0.0, dir * a, shift_m, 0.0, a * swept_radius(), clear0)) return false;
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
