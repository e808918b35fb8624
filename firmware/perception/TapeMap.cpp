#include "firmware/perception/TapeMap.hpp"

#include <cmath>

namespace carril::fw {

namespace {
constexpr double kMinSpacing = 0.06;    // [m] between stored points: headings from shorter
                                        // steps would be mostly pixel noise
constexpr double kBackExtension = 1.5;  // tape assumed straight behind the first point [m]
// A frame's last two points are dropped when both are steps shorter than this (two minimum
// spacings) and they turn the path by more than kTailMaxTurnRad together.
constexpr double kTailMaxStep = 2.0 * kMinSpacing;  // [m]
constexpr double kTailMaxTurnRad = 2.356;           // 135 deg
// kStaleFrames frames in a row of at least kMinFramePoints points, none of which follows
// memory, drop up to kMaxStaleTail of memory's last points [frames, points, points].
constexpr int kStaleFrames = 15;
constexpr std::size_t kMinFramePoints = 4;
constexpr int kMaxStaleTail = 2;

}  // namespace

void TapeMap::add(const Pose2& odom, const Vec2* pts_robot, std::size_t n) {
  if (n < 2) return;
  // The new frame sees the tape from its nearest visible point on, better than memory does: keep
  // only remembered points behind that point (already passed under the camera).
  const double near_x = pts_robot[0].x() - 0.005;
  StaticVector<Vec2, kMaxPoints> kept;
  const PoseFrame frame(odom);
  for (const Vec2& p : pts_) {
    if (frame.to_robot(p).x() < near_x) kept.push_back(p);
  }
  // Trim the oldest points (far behind by then) so there is room.
  const std::size_t room = kMaxPoints - n;
  const std::size_t skip = kept.size() > room ? kept.size() - room : 0;
  pts_.clear();
  for (std::size_t i = skip; i < kept.size(); ++i) pts_.push_back(kept[i]);
  const auto doubles_back = [&](const Vec2& w) {
    const Vec2 a = pts_.back() - pts_[pts_.size() - 2], b = w - pts_.back();
    return a.dot(b) < -0.2 * a.norm() * b.norm();
  };
  const auto append_frame = [&]() {
    std::size_t added = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 w = frame.to_world(pts_robot[i]);
      if (!pts_.empty() && (w - pts_.back()).norm() < kMinSpacing) continue;
      // Tape does not double back within a few centimetres: a point that would turn the path by
      // more than about 100 deg is a centroid of a band that straddles both legs of a corner.
      if (pts_.size() >= 2 && doubles_back(w)) continue;
      pts_.push_back(w);
      ++added;
    }
    return added;
  };
  // Frames of several points none of which could follow memory, kStaleFrames in a row: memory's
  // end is what is stale (centroids from frames that saw both legs of a corner, pointing on along
  // the old leg). Kept, it would turn every later frame away, and the tape ahead would never be
  // remembered (the robot stood on a corner's new leg, seeing it, until its time ran out). Up to
  // kMaxStaleTail of memory's last points are dropped and the frame added again. (A few such
  // frames are usual at a corner, until the robot has passed memory's end.)
  const bool none = append_frame() == 0 && n >= kMinFramePoints;
  stale_frames_ = none ? stale_frames_ + 1 : 0;
  if (stale_frames_ >= kStaleFrames) {
    stale_frames_ = 0;
    for (int k = 0; k < kMaxStaleTail && pts_.size() >= 3; ++k) {
      pts_.pop_back();
      if (!doubles_back(frame.to_world(pts_robot[0]))) break;
    }
    append_frame();
  }
  // A ragged tail: the frame's last two points, each a short step, turning the path back on
  // itself (together by more than 135 deg). A strip of tape lying across the image (a corner's
  // new leg along the bottom of the view) gives centroids of row bands that bunch in its middle,
  // the last ones from its ragged top rows; they zig-zag back across the corner, and the
  // controller would steer by that false turn. A real corner turns the path once.
  while (pts_.size() >= 4) {
    const std::size_t n_pts = pts_.size();
    const Vec2 a = pts_[n_pts - 3] - pts_[n_pts - 4], b = pts_[n_pts - 2] - pts_[n_pts - 3],
               c = pts_.back() - pts_[n_pts - 2];
    if (b.norm() >= kTailMaxStep || c.norm() >= kTailMaxStep) break;
    const auto turn = [](const Vec2& u, const Vec2& v) {
      return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
    };
    if (std::fabs(turn(a, b) + turn(b, c)) <= kTailMaxTurnRad) break;
    pts_.pop_back();
    pts_.pop_back();
  }
}

bool TapeMap::far_segment(double span_m, Vec2& point, double& heading) const {
  if (pts_.size() < 2) return false;
  const Vec2& last = pts_.back();
  const std::size_t n = pts_.size();
  // Back from the last point up to span_m (and one point beyond), while the stretch stays
  // straight: just past a corner only the new leg's points give its direction (a chord across
  // the corner points half-way between the legs).
  const auto straight = [&](std::size_t from) {
    const Vec2 d = last - pts_[from];
    const double len = d.norm();
    if (len < 1e-3) return true;
    for (std::size_t k = from + 1; k + 1 < n; ++k) {
      const Vec2 q = pts_[k] - pts_[from];
      if (std::fabs(d.x() * q.y() - d.y() * q.x()) / len > kStraightTolM) return false;
    }
    return true;
  };
  std::size_t i = n - 1;
  while (i > 0 && straight(i - 1)) {
    --i;
    if ((pts_[i] - last).norm() >= span_m) break;
  }
  const Vec2 d = last - pts_[i];
  if (d.norm() < 1e-3) return false;
  point = last;
  heading = std::atan2(d.y(), d.x());
  return true;
}

double TapeMap::start_curvature() const {
  // Heading change between the first two 0.15 m chords of the remembered tape.
  std::size_t i1 = 1;
  while (i1 < pts_.size() && (pts_[i1] - pts_[0]).norm() < 0.15) ++i1;
  std::size_t i2 = i1 + 1;
  while (i2 < pts_.size() && (pts_[i2] - pts_[i1]).norm() < 0.15) ++i2;
  if (i2 >= pts_.size()) return 0.0;
  const Vec2 c1 = pts_[i1] - pts_[0], c2 = pts_[i2] - pts_[i1];
  const double dh = wrap_angle(std::atan2(c2.y(), c2.x()) - std::atan2(c1.y(), c1.x()));
  return dh / (0.5 * (c1.norm() + c2.norm()));
}

bool TapeMap::continues(const Pose2& odom, const Vec2* pts_robot, std::size_t n,
                        bool& extends) const {
  extends = false;
  if (pts_.size() < 2 || n < 2) return false;
  const PoseFrame frame(odom);
  const Vec2 near = frame.to_world(pts_robot[0]), far = frame.to_world(pts_robot[n - 1]);
  const double len = (far - near).norm();
  if (len < kMinPieceM) return false;  // a speck has no direction to agree with
  const Vec2 u = (far - near) / len;
  const auto angle = [](const Vec2& a, const Vec2& b) {
    return std::fabs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
  };
  // On memory: every point within a segment's tolerance of the remembered path, which runs the
  // piece's way where the piece's middle is.
  const std::size_t last = pts_.size() - 1;
  bool on_path = true;
  Vec2 mid_dir = Vec2::Zero();
  for (std::size_t j = 0; j <= n && on_path; ++j) {
    const Vec2 q = j < n ? frame.to_world(pts_robot[j]) : Vec2(0.5 * (near + far));
    double best = 1e18;  // the best segment's distance beyond its tolerance [m]
    for (std::size_t i = 0; i < last; ++i) {
      const Vec2 d = pts_[i + 1] - pts_[i];
      const double len2 = d.squaredNorm();
      const double t = len2 > 1e-12 ? clampd((q - pts_[i]).dot(d) / len2, 0.0, 1.0) : 0.0;
      // A long segment is memory's own bridge over tape it did not see (a gap, an obstacle):
      // the tape there may bend, as across a gap.
      const double excess = (pts_[i] + t * d - q).norm() - tolerance(std::sqrt(len2));
      if (excess < best) {
        best = excess;
        if (j == n) mid_dir = d;
      }
    }
    if (j < n) on_path = best <= 0.0;
  }
  if (on_path) return angle(mid_dir, u) <= kContinueMaxTurnRad;
  // Past memory's end, across a gap: the piece reaches beyond the end and begins no further than
  // kContinueReachM past it, its line passes within the tolerance of the end (the tolerance
  // growing with the gap, for a tape that bends), and it runs the way memory's last 15 cm ran.
  const Vec2 end = pts_[last];
  std::size_t back = last;
  while (back > 0 && (end - pts_[back]).norm() < 0.15) --back;
  const Vec2 end_dir = end - pts_[back];
  if (end_dir.norm() < 1e-3 || (far - end).dot(u) <= 0.0) return false;
  const double gap = (near - end).dot(u);
  const Vec2 off = end - near;
  const double offset = std::fabs(u.x() * off.y() - u.y() * off.x());
  const bool ok = gap <= kContinueReachM && offset <= tolerance(gap) &&
                  angle(end_dir, u) <= kContinueMaxTurnRad;
  extends = ok;
  return ok;
}

TapeMap::Nearest TapeMap::nearest(const Vec2& q) const {
  // Nearest point on the polyline, with the first segment extended backwards (the robot may not
  // have reached the first remembered point yet).
  Nearest n;
  double best = 1e18;
  for (std::size_t i = 0; i + 1 < pts_.size(); ++i) {
    const Vec2 a = pts_[i], d = pts_[i + 1] - pts_[i];
    const double len2 = d.squaredNorm();
    if (len2 < 1e-12) continue;
    double u = (q - a).dot(d) / len2;
    const double lo = i == 0 ? -kBackExtension / std::sqrt(len2) : 0.0;
    u = clampd(u, lo, 1.0);
    const double dist2 = (a + u * d - q).squaredNorm();
    if (dist2 < best) {
      best = dist2;
      n.seg = i;
      n.u = u;
    }
  }
  return n;
}

void TapeMap::continue_behind(const Vec2& q, double seg_len, Vec2& nearest,
                              double& tape_heading) const {
  // Behind the first remembered point: continue the tape backwards along the circle it bends
  // on there, so a robot standing on a curve is not told it is off the tape. The first chord's
  // direction is the tangent at its middle; the tangent at the point is half a chord back.
  const Vec2 a = pts_[0];
  const double k = start_curvature();
  const double h0 = tape_heading - 0.5 * k * seg_len;
  const Vec2 t0(std::cos(h0), std::sin(h0));
  const Vec2 n0(-t0.y(), t0.x());
  if (std::fabs(k) < 1e-4) {
    nearest = a + (q - a).dot(t0) * t0;
    tape_heading = h0;
    return;
  }
  const Vec2 c = a + n0 / k;  // centre (left of the tape for k > 0)
  const Vec2 rq = q - c, ra = a - c;
  const double r = 1.0 / std::fabs(k);
  nearest = rq.norm() > 1e-9 ? Vec2(c + rq * (r / rq.norm())) : a;
  const Vec2 rn = nearest - c;
  // Angle swept about the centre from the first point to the nearest one.
  const double phi = std::atan2(ra.x() * rn.y() - ra.y() * rn.x(), ra.dot(rn));
  tape_heading = h0 + phi;  // along a circle the heading turns by the angle swept
}

void TapeMap::walk_ahead(const Nearest& n, const Vec2& nearest, const Vec2& dir, double seg_len,
                         double tape_heading, double lookahead_m, double preview_m,
                         const Pose2& odom, TrackState& t) const {
  // Walk forward along the path for the look-ahead point, the preview curvature and corners.
  double walked = (1.0 - n.u) * seg_len;
  Vec2 la = pts_[n.seg + 1];
  bool la_set = walked >= lookahead_m;
  if (la_set) la = nearest + dir * lookahead_m;
  double prev_heading = tape_heading;
  double turn_sum = 0.0;
  double preview_used = 0.0;
  double sharpest = 0.0;
  for (std::size_t i = n.seg + 1; i + 1 < pts_.size(); ++i) {
    const Vec2 s = pts_[i + 1] - pts_[i];
    const double len = s.norm();
    if (len < 1e-9) continue;
    const double h = std::atan2(s.y(), s.x());
    const double dh = wrap_angle(h - prev_heading);
    if (walked <= preview_m) {
      turn_sum += dh;
      preview_used = walked + len;
      // A corner is a sharp heading change concentrated over a short stretch.
      if (std::fabs(dh) > std::fabs(sharpest)) {
        sharpest = dh;
        t.corner_dist_m = walked;
        t.corner_turn_rad = dh;
      }
    }
    if (!la_set && walked + len >= lookahead_m) {
      la = pts_[i] + s / len * (lookahead_m - walked);
      la_set = true;
    }
    walked += len;
    prev_heading = h;
  }
  t.remaining_m = walked;
  if (!la_set) la = pts_.back();
  t.lookahead = to_robot(odom, la);
  t.curvature_ahead = preview_used > 1e-3 ? turn_sum / preview_used : 0.0;
}

TrackState TapeMap::track(const Pose2& odom, double lookahead_m, double preview_m) const {
  TrackState t;
  if (pts_.size() < 2) return t;
  const Vec2 q(odom.x, odom.y);
  const Nearest n = nearest(q);
  const Vec2 a = pts_[n.seg], d = pts_[n.seg + 1] - pts_[n.seg];
  const double seg_len = d.norm();
  if (seg_len < 1e-9) return t;
  const Vec2 dir = d / seg_len;
  Vec2 nearest_pt = a + n.u * d;
  double tape_heading = std::atan2(dir.y(), dir.x());
  if (n.seg == 0 && n.u < 0.0) continue_behind(q, seg_len, nearest_pt, tape_heading);
  // Signed offset: + when the tape is to the robot's left.
  t.lateral_m = to_robot(odom, nearest_pt).y();
  t.tape_heading_odom = tape_heading;
  t.heading_err_rad = wrap_angle(tape_heading - odom.yaw);
  walk_ahead(n, nearest_pt, dir, seg_len, tape_heading, lookahead_m, preview_m, odom, t);
  t.valid = true;
  return t;
}

}  // namespace carril::fw
