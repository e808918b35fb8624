// The waypoint mission's BYPASS: an obstacle in the body's corridor to the target is gone round
// by following its edge at the keeping distance, on the shorter side, until the way to the target
// is clear (Bug2's leave rule), or the edge is lost.
#include <cmath>

#include "firmware/mission/WaypointBypass.hpp"
#include "firmware/mission/WaypointMission.hpp"

namespace carril::fw {

using namespace waypoint_bypass;

// The body's corridor toward the target meets a cell within the bypass distance, nearer than the
// target and not at it (a target at an obstacle cannot be gone round to).
bool WaypointMission::in_the_way(const Pose2& pose, const Vec2& to_target, double dist) const {
  const Vec2 dir = to_robot(Pose2{0.0, 0.0, pose.yaw}, to_target);
  const double look = std::fmin(keep_m() + kEnterMarginM, dist);
  if (guard_.corridor(dir, guard_.half_width() + guard_.margin(), look).first_m >= look) {
    return false;
  }
  return guard_.distance_to(dir * dist) > keep_m();
}

// Round on the side the obstacle in the corridor to the target leaves more of (the shorter way),
// or, when it lies square across it, the side VFF's push leans to (away from the clutter). The
// edge followed starts at the corridor's first cell (the nearest cell without one).
void WaypointMission::start_bypass(const Pose2& pose, const Vec2& to_target) {
  const Vec2 dir = to_robot(Pose2{0.0, 0.0, pose.yaw}, to_target);
  const BodyGuard::Corridor c = guard_.corridor(dir, guard_.half_width() + guard_.margin(),
                                                keep_m() + kEnterMarginM, kSideDepthM);
  const BodyGuard::Nearest n = guard_.nearest();
  if (c.cells > 0 && std::fabs(c.mean_side_m) > kSideTieM) {
    side_ = c.mean_side_m > 0.0 ? -1 : 1;
  } else {
    Vec2 push = vff_.repulsion();
    if (push.squaredNorm() < 1e-12) push = -n.p;
    side_ = to_target.x() * push.y() - to_target.y() * push.x() < 0.0 ? -1 : 1;
  }
  edge_ = to_world(pose, c.cells > 0 ? c.first_p : n.p);
  bypass_ = true;
  bypass_from_ = Vec2(pose.x, pose.y);
  bypass_left_ = false;
  bypass_best_ = closest_;
  ++bypasses_;
  go(State::Drive, kBypass);
}

// The edge followed: the cell nearest the centre within kTrackM of where it was last tick. Another
// obstacle met straight ahead within the keeping distance (a gap too narrow to follow the edge
// through) becomes the edge: the two are gone round as one, on the same side.
BodyGuard::Nearest WaypointMission::follow_edge(const Pose2& pose) {
  const BodyGuard::Corridor ahead =
      guard_.corridor(Vec2(1.0, 0.0), guard_.half_width() + guard_.margin(), keep_m());
  if (ahead.first_m < keep_m() && (to_world(pose, ahead.first_p) - edge_).norm() > kTrackM) {
    edge_ = to_world(pose, ahead.first_p);
  }
  const BodyGuard::Nearest e = guard_.nearest_around(to_robot(pose, edge_), kTrackM);
  if (e.found) edge_ = to_world(pose, e.p);
  return e;
}

// The edge followed is lost, or the robot is closer to the target than it ever was before the
// bypass (as in Bug2: no drive-bypass cycle repeats) and the body's corridor toward the target (a
// little wider than the one that began the bypass) is clear for kClearAheadM.
bool WaypointMission::bypass_over(const Pose2& pose, const BodyGuard::Nearest& edge,
                                  const Vec2& to_target, double dist) const {
  if (!edge.found || edge.d_m > keep_m() + kLostM) return true;
  const Vec2 dir = to_robot(Pose2{0.0, 0.0, pose.yaw}, to_target);
  const double look = std::fmin(kClearAheadM, dist);
  const double half = guard_.half_width() + guard_.margin() + kLeaveWidenM;
  return dist < bypass_best_ && guard_.corridor(dir, half, look).first_m >= look;
}

// Along the edge with it on side_'s other hand, steering back to the keeping distance.
Twist WaypointMission::bypass_twist(const BodyGuard::Nearest& edge) const {
  Twist t;
  if (!edge.found || edge.d_m < 1e-6) return t;
  const Vec2 away = -edge.p / edge.d_m;  // body frame, edge to centre
  const Vec2 along = side_ > 0 ? Vec2(away.y(), -away.x()) : Vec2(-away.y(), away.x());
  const Vec2 h = along + clampd(kKeepGain * (keep_m() - edge.d_m), -1.0, 1.0) * away;
  const double err = std::atan2(h.y(), h.x());
  const VffConfig& v = cfg_.vff;
  t.wz = clampd(v.turn_gain * err, -v.max_yaw_rate_radps, v.max_yaw_rate_radps);
  if (std::fabs(err) <= v.turn_in_place_rad) t.vx = cfg_.bypass_speed_mps * std::cos(err);
  return t;
}

}  // namespace carril::fw
