#include "firmware/behavior/BypassPlanner.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {
struct TapeFrame {
  Vec2 o;
  Vec2 u, n;
  Vec2 to(const Vec2& p) const { return {(p - o).dot(u), (p - o).dot(n)}; }
  Vec2 from(double x, double y) const { return o + x * u + y * n; }
};
TapeFrame frame_of(const Vec2& o, double h) {
  return {o, Vec2(std::cos(h), std::sin(h)), Vec2(-std::sin(h), std::cos(h))};
}
}  // namespace

BypassPlan BypassPlanner::plan(const ObstacleField& f, const Pose2& odom, const Vec2& tape_point,
                               double tape_heading, const RollingGrid<std::uint8_t>* costmap,
                               int excluded_side) const {
  BypassPlan p;
  p.origin = tape_point;
  p.heading = tape_heading;
  const TapeFrame tf = frame_of(tape_point, tape_heading);
  const auto& pts = f.points();
  const double x_robot = tf.to(Vec2(odom.x, odom.y)).x();
  // The nearest point ahead within the robot's corridor along the tape, and near enough.
  const double half = fp_.half_width_m + cfg_.corridor_margin_m;
  const double x_reach = x_robot + fp_.half_length_m + cfg_.lookahead_m;
  std::size_t nearest = pts.size();
  double best = 1e9;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2 q = tf.to(pts[i]);
    if (q.x() > x_robot && q.x() <= x_reach && std::fabs(q.y()) <= half && q.x() < best) {
      best = q.x();
      nearest = i;
    }
  }
  if (nearest == pts.size()) return p;  // nothing ahead any more
  // The obstacle: the run of consecutive beams round the nearest hit, gaps under 0.3 m.
  std::size_t lo = nearest, hi = nearest;
  while (lo > 0 && (pts[lo - 1] - pts[lo]).norm() < 0.3) --lo;
  while (hi + 1 < pts.size() && (pts[hi + 1] - pts[hi]).norm() < 0.3) ++hi;
  p.x_near = 1e9, p.x_far = -1e9, p.y_min = 1e9, p.y_max = -1e9;
  for (std::size_t i = lo; i <= hi; ++i) {
    const Vec2 q = tf.to(pts[i]);
    p.x_near = std::fmin(p.x_near, q.x());
    p.x_far = std::fmax(p.x_far, q.x());
    p.y_min = std::fmin(p.y_min, q.y());
    p.y_max = std::fmax(p.y_max, q.y());
  }
  // The far side is not seen yet: assume the obstacle is about as deep as it is wide.
  p.x_far = std::fmax(p.x_far, p.x_near + std::fmin(p.y_max - p.y_min, 3.0));
  // Whatever else stands where the robot would rejoin the tape is passed in the same bypass.
  if (!cover_rejoin(p, f, costmap)) {
    p.blocked = true;
    return p;
  }
  // Room on each side: the nearest other thing beside the obstacle, along its length.
  double free_left = cfg_.max_lateral_m, free_right = cfg_.max_lateral_m;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i >= lo && i <= hi) continue;
    const Vec2 q = tf.to(pts[i]);
    if (q.x() < p.x_near - fp_.half_length_m - 0.3 || q.x() > p.x_far + fp_.half_length_m + 0.5)
      continue;
    if (q.y() > p.y_max) free_left = std::fmin(free_left, q.y() - p.y_max);
    if (q.y() < p.y_min) free_right = std::fmin(free_right, p.y_min - q.y());
  }
  const double need = 2.0 * (cfg_.clearance_m + fp_.half_width_m);
  const double reach_left = p.y_max + cfg_.clearance_m + fp_.half_width_m;
  const double reach_right = -(p.y_min - cfg_.clearance_m - fp_.half_width_m);
  const bool left_ok = excluded_side <= 0 && free_left >= need && reach_left <= cfg_.max_lateral_m;
  const bool right_ok =
      excluded_side >= 0 && free_right >= need && reach_right <= cfg_.max_lateral_m;
  if (!left_ok && !right_ok) {
    p.blocked = true;
    return p;
  }
  // The freer side; the shorter detour when both are ample.
  if (left_ok && right_ok) {
    p.side = (free_left >= need + 0.5 && free_right >= need + 0.5)
                 ? (reach_left <= reach_right ? 1 : -1)
                 : (free_left >= free_right ? 1 : -1);
  } else {
    p.side = left_ok ? 1 : -1;
  }
  p.lateral = p.side > 0 ? reach_left : -reach_right;
  set_waypoints(p, x_robot);
  p.ok = true;
  if (costmap != nullptr) {
    // The costmap may hold more of the obstacle than this scan's outline (a lidar on one corner
    // sees one flank): the lane moves out in steps of kLaneStepM, up to max_lateral_m, until
    // the body clears it; then the other side, where the outline allows it.
    BypassPlan q = p;
    const auto clear_lane = [&](int side, double reach) {
      q.side = side;
      for (int k = 0; reach + k * kLaneStepM <= cfg_.max_lateral_m + 1e-9; ++k) {
        q.lateral = side * (reach + k * kLaneStepM);
        set_waypoints(q, x_robot);
        if (lane_clear(q, odom, 0, *costmap)) return true;
      }
      return false;
    };
    if (clear_lane(p.side, p.side > 0 ? reach_left : reach_right)) return q;
    const bool other_ok = p.side > 0 ? right_ok : left_ok;
    if (other_ok && clear_lane(-p.side, p.side > 0 ? reach_right : reach_left)) return q;
    p.ok = false;
    p.blocked = true;
  }
  return p;
}

bool BypassPlanner::lane_clear(const BypassPlan& p, const Pose2& from, std::size_t first,
                               const RollingGrid<std::uint8_t>& costmap) const {
  const double res = costmap.resolution();
  // A lethal cell's centre may be up to one cell from the obstacle point it holds.
  const double margin = cfg_.emergency_m + res;
  const double turn_radius = fp_.circumscribed_m() + cfg_.emergency_m;
  const Vec2 start(from.x, from.y);
  const Rect here = grown(start, from.yaw, margin);
  Vec2 a = start;
  double yaw = from.yaw;
  for (std::size_t i = first; i < p.waypoints.size(); ++i) {
    const Vec2 b = p.waypoints[i];
    if ((b - a).norm() < 1e-6) continue;
    const double leg_yaw = holonomic_ ? p.heading : std::atan2(b.y() - a.y(), b.x() - a.x());
    // A differential robot turns on the spot onto the leg first.
    if (!holonomic_ && std::fabs(wrap_angle(leg_yaw - yaw)) > 0.05 && (a - start).norm() >= res &&
        !disc_clear(a, turn_radius, costmap))
      return false;
    yaw = leg_yaw;
    if (!sweep_clear(grown(a, yaw, margin), grown(b, yaw, margin), here, costmap)) return false;
    a = b;
  }
  // ...and at the end onto the tape again.
  if (!holonomic_ && std::fabs(wrap_angle(p.heading - yaw)) > 0.05 && (a - start).norm() >= res &&
      !disc_clear(a, turn_radius, costmap))
    return false;
  return true;
}

BypassPlanner::Rect BypassPlanner::grown(const Vec2& c, double yaw, double margin) const {
  Rect r;
  r.c = c;
  r.u = Vec2(std::cos(yaw), std::sin(yaw));
  r.hl = fp_.half_length_m + margin;
  r.hw = fp_.half_width_m + margin;
  return r;
}

bool BypassPlanner::sweep_clear(const Rect& r0, const Rect& r1, const Rect& here,
                                const RollingGrid<std::uint8_t>& costmap) {
  // The area the body sweeps sliding from r0 to r1 without turning: the convex hull of both
  // rectangles' corners (Andrew's monotone chain over the 8 points).
  constexpr int n = 8;
  Vec2 pts[n];
  for (int i = 0; i < n; ++i) {
    const Rect& r = i < 4 ? r0 : r1;
    const double s = (i & 1) ? 1.0 : -1.0, t = (i & 2) ? 1.0 : -1.0;
    pts[i] = r.c + s * r.hl * r.u + t * r.hw * Vec2(-r.u.y(), r.u.x());
  }
  // Sorted by x, then y (insertion sort: 8 points).
  for (int i = 1; i < n; ++i) {
    for (int j = i; j > 0; --j) {
      const Vec2 &a = pts[j - 1], &b = pts[j];
      if (a.x() < b.x() || (a.x() == b.x() && a.y() <= b.y())) break;
      std::swap(pts[j - 1], pts[j]);
    }
  }
  const auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  Vec2 hull[16];
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  const int m = k - 1;  // the last point repeats the first
  double ymin = hull[0].y(), ymax = hull[0].y();
  for (int i = 1; i < m; ++i) {
    ymin = std::fmin(ymin, hull[i].y());
    ymax = std::fmax(ymax, hull[i].y());
  }
  // Row by row, the cells whose centres lie inside the hull.
  const double res = costmap.resolution();
  const Vec2 hv(-here.u.y(), here.u.x());
  for (int cy = costmap.cell_of(ymin); cy <= costmap.cell_of(ymax); ++cy) {
    const double yc = costmap.center_of(cy);
    double xl = 1e300, xr = -1e300;
    for (int i = 0; i < m; ++i) {
      const Vec2 &e0 = hull[i], &e1 = hull[i + 1];
      if ((yc < e0.y()) == (yc < e1.y())) continue;  // the edge does not cross this row
      const double x = e0.x() + (yc - e0.y()) * (e1.x() - e0.x()) / (e1.y() - e0.y());
      xl = std::fmin(xl, x);
      xr = std::fmax(xr, x);
    }
    if (xl > xr) continue;
    const int cx0 = static_cast<int>(std::ceil(xl / res - 0.5));
    const int cx1 = static_cast<int>(std::floor(xr / res - 0.5));
    for (int cx = cx0; cx <= cx1; ++cx) {
      if (!costmap.contains(cx, cy) || costmap.at(cx, cy) != cost::kLethal) continue;
      // Where the robot stands now is not judged (the emergency stop guards it).
      const Vec2 d = Vec2(costmap.center_of(cx), yc) - here.c;
      if (std::fabs(d.dot(here.u)) <= here.hl && std::fabs(d.dot(hv)) <= here.hw) continue;
      return false;
    }
  }
  return true;
}

bool BypassPlanner::disc_clear(const Vec2& c, double radius,
                               const RollingGrid<std::uint8_t>& costmap) {
  const double res = costmap.resolution();
  const int x0 = costmap.cell_of(c.x() - radius), x1 = costmap.cell_of(c.x() + radius);
  const int y0 = costmap.cell_of(c.y() - radius), y1 = costmap.cell_of(c.y() + radius);
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      if (!costmap.contains(cx, cy) || costmap.at(cx, cy) != cost::kLethal) continue;
      // The cell's nearest point to the centre.
      const double nx = clampd(c.x(), cx * res, (cx + 1) * res);
      const double ny = clampd(c.y(), cy * res, (cy + 1) * res);
      if (std::hypot(nx - c.x(), ny - c.y()) < radius) return false;
    }
  }
  return true;
}

bool BypassPlanner::cover_rejoin(BypassPlan& p, const ObstacleField& f,
                                 const RollingGrid<std::uint8_t>* costmap) const {
  const TapeFrame tf = frame_of(p.origin, p.heading);
  // The band the robot takes on the tape again, with its clearance each side, and how far along
  // it needs to get back onto it: from the obstacle's far end, the clearance, a body length and
  // the rejoin leg.
  const double band = fp_.half_width_m + cfg_.clearance_m;
  const double need = 2.0 * cfg_.clearance_m + 2.0 * fp_.half_length_m + 0.15;
  const auto& pts = f.points();
  for (int round = 0; round < kMaxMerges; ++round) {
    const double x0 = p.x_far, x1 = p.x_far + need;
    double far = p.x_far, y_min = p.y_min, y_max = p.y_max;
    double near = 1e9, lo_y = 1e9, hi_y = -1e9;  // what was found this round
    bool found = false;
    const auto add = [&](const Vec2& q) {
      found = true;
      far = std::fmax(far, q.x());
      near = std::fmin(near, q.x());
      lo_y = std::fmin(lo_y, q.y());
      hi_y = std::fmax(hi_y, q.y());
    };
    const auto take = [&](const Vec2& q) {
      if (q.x() > x0 && q.x() <= x1 && std::fabs(q.y()) <= band) add(q);
    };
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2 q = tf.to(pts[i]);
      if (q.x() <= x0 || q.x() > x1 || std::fabs(q.y()) > band) continue;
      // The whole run of beams it belongs to (its far side, its width), as for the first one.
      std::size_t lo = i, hi = i;
      while (lo > 0 && (pts[lo - 1] - pts[lo]).norm() < 0.3) --lo;
      while (hi + 1 < pts.size() && (pts[hi + 1] - pts[hi]).norm() < 0.3) ++hi;
      for (std::size_t j = lo; j <= hi; ++j) add(tf.to(pts[j]));
      i = hi;
    }
    if (costmap != nullptr && costmap->ready()) {
      // The costmap holds what the scan cannot see now (behind the first obstacle, say): its
      // lethal cells in the zone, over the zone's bounding box in the costmap's frame.
      const Vec2 c[4] = {tf.from(x0, -band), tf.from(x0, band), tf.from(x1, -band),
                         tf.from(x1, band)};
      double ax = c[0].x(), bx = c[0].x(), ay = c[0].y(), by = c[0].y();
      for (const Vec2& k : c) {
        ax = std::fmin(ax, k.x());
        bx = std::fmax(bx, k.x());
        ay = std::fmin(ay, k.y());
        by = std::fmax(by, k.y());
      }
      for (int cy = costmap->cell_of(ay); cy <= costmap->cell_of(by); ++cy) {
        for (int cx = costmap->cell_of(ax); cx <= costmap->cell_of(bx); ++cx) {
          if (!costmap->contains(cx, cy) || costmap->at(cx, cy) != cost::kLethal) continue;
          take(tf.to(Vec2(costmap->center_of(cx), costmap->center_of(cy))));
        }
      }
    }
    if (!found) return true;
    // Its far side unseen: as deep as it is wide, as for the first.
    p.x_far = std::fmax(far, near + std::fmin(hi_y - lo_y, 3.0));
    p.y_min = std::fmin(y_min, lo_y);
    p.y_max = std::fmax(y_max, hi_y);
    if (p.x_far - p.x_near > kMaxBypassM) return false;
  }
  return false;  // more than kMaxMerges obstacles in a row: not a bypass any more
}

void BypassPlanner::set_waypoints(BypassPlan& p, double x_robot) const {
  const TapeFrame tf = frame_of(p.origin, p.heading);
  const double past = p.x_far + cfg_.clearance_m + fp_.half_length_m;
  p.waypoints.clear();
  p.waypoints.push_back(tf.from(x_robot, p.lateral));  // step aside
  p.waypoints.push_back(tf.from(past, p.lateral));     // pass it
  p.waypoints.push_back(tf.from(past + 0.15, 0.0));    // back onto the tape beyond it
}

void BypassPlanner::refine(const ObstacleField& f, BypassPlan& p,
                           const RollingGrid<std::uint8_t>* costmap) const {
  if (!p.ok) return;
  const TapeFrame tf = frame_of(p.origin, p.heading);
  // Points close round the known outline belong to the obstacle: what was hidden from the
  // first view (its far side, or the part behind its curve for a sensor off to one side).
  double far = p.x_far, y_min = p.y_min, y_max = p.y_max;
  for (const Vec2& w : f.points()) {
    const Vec2 q = tf.to(w);
    if (q.x() >= p.x_near - 0.1 && q.x() <= p.x_near + 3.0 && q.y() >= p.y_min - 0.2 &&
        q.y() <= p.y_max + 0.2) {
      far = std::fmax(far, q.x());
      y_min = std::fmin(y_min, q.y());
      y_max = std::fmax(y_max, q.y());
    }
  }
  // And whatever now shows where the robot would rejoin the tape (a second obstacle behind the
  // first, hidden from the first view). Running on too far, it is left to the lane check.
  BypassPlan q = p;
  q.x_far = far;
  q.y_min = y_min;
  q.y_max = y_max;
  if (!cover_rejoin(q, f, costmap)) q = p;
  const bool deeper = q.x_far > p.x_far + 0.02;
  const bool wider =
      (p.side > 0 && q.y_max > p.y_max + 0.01) || (p.side < 0 && q.y_min < p.y_min - 0.01);
  if (!deeper && !wider) return;
  p.x_far = q.x_far;
  p.y_min = q.y_min;
  p.y_max = q.y_max;
  // The lane only ever moves away from the obstacle.
  const double lane = p.side > 0 ? p.y_max + cfg_.clearance_m + fp_.half_width_m
                                 : p.y_min - cfg_.clearance_m - fp_.half_width_m;
  if (std::fabs(lane) > std::fabs(p.lateral)) p.lateral = lane;
  const Vec2 first = tf.to(p.waypoints[0]);
  set_waypoints(p, first.x());
}

std::span<const Param<AvoidConfig>> AvoidConfig::params() {
  using C = AvoidConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, corridor_margin_m, "m", 0.0, 1.0,
                   "bypass corridor: robot width + this each side"),
      CARRIL_PARAM(C, clearance_m, "m", 0.0, 2.0, "body-to-obstacle clearance while passing"),
      CARRIL_PARAM(C, speed_mps, "m/s", 0.01, 2.0, "bypass speed"),
      CARRIL_PARAM(C, emergency_m, "m", 0.0, 1.0,
                   "anything this close to the body stops the robot"),
      CARRIL_PARAM(C, max_lateral_m, "m", 0.1, 20.0, "never detour further from the tape"),
      CARRIL_PARAM(C, blocked_timeout_s, "s", 0.1, 60.0,
                   "stopped this long by something in the way: give up"),
      CARRIL_PARAM(C, lookahead_m, "m", 0.1, 20.0,
                   "only an obstacle starting this close ahead of the bumper (along the tape, "
                   "after aligning) is planned round"),
  };
  return kParams;
}

Status AvoidConfig::validate() const {
  return Checks("behavior.avoid").params(*this, params()).result();
}

}  // namespace carril::fw
