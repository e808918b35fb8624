#include "host_sim/metrics/RunMetrics.hpp"

#include <algorithm>
#include <cmath>

namespace carril::sim {
namespace {

// Progress tracking (see add()).
constexpr double kWindowM = 3.0;   // how far ahead a rejoin may be credited, plus the detour [m]
constexpr double kOnPathM = 0.35;  // robot centre this close to the tape counts as on it [m]
constexpr double kDoneRemainingM = 0.05;  // this little left of the path counts as all of it [m]
// End mark stop.
constexpr double kEndRadiusM = 0.25;  // centre within this of an end mark's centre [m]
constexpr double kStoppedSpeedMps = 0.01;
constexpr double kStoppedWzRadps = 0.02;

double dist(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

}  // namespace

RunMetrics::RunMetrics(const Scenario& scenario) : scenario_(scenario), path_(scenario) {
  for (const MarkSpec& m : scenario.marks) {
    if (m.color == scenario.mission.end_color) end_marks_.push_back(m.center);
  }
}

double RunMetrics::add(const TickSample& s) {
  const Vec2 q{s.pose.x, s.pose.y};
  // A non-finite pose carries no information and would poison every sum (and trap).
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(s.t_s)) return 0.0;

  if (started_) {
    path_length_m_ += dist(last_xy_, q);
    off_path_m_ += dist(last_xy_, q);
  } else {
    first_t_s_ = s.t_s;
  }
  last_t_s_ = s.t_s;
  last_xy_ = q;
  if (std::isfinite(s.wz_radps)) max_abs_wz_ = std::max(max_abs_wz_, std::abs(s.wz_radps));

  double cross_track = 0.0;
  if (!path_.empty()) {
    cross_track = path_.nearest(q).dist_m;

    // Progress: a monotone arc position s_m_. It only moves forward, to the nearest tape point
    // within the window [s, s + W] ahead, and only while the robot is on the tape (within
    // kOnPathM of that point). Leaving the tape for a detour advances nothing; rejoining up to W
    // further on credits the whole skipped stretch, W being kWindowM plus what the robot drove
    // since it was last on the tape (a long bypass round two obstacles is a bypass: it drove at
    // least as far as it skips); jumping to a far part of the path (a shortcut, shorter than
    // the stretch it skips) finds nothing near within the window and is never credited.
    const double len = path_.length_m();
    if (!started_) {
      s_m_ = path_.nearest(q).s_m;
      s0_m_ = s_m_;
    } else {
      const double reach = kWindowM + off_path_m_;
      const double window = path_.closed() ? std::min(reach, len / 2.0) : reach;
      const PathPoint p = path_.nearest_in(q, s_m_, s_m_ + window);
      if (p.dist_m <= kOnPathM) {
        off_path_m_ = 0.0;
        double delta = p.s_m - s_m_;
        // On a loop the window may wrap past the seam; legitimate advances are in [0, W] with
        // W <= L/2, so a clearly negative delta is a wrap and a tiny one is rounding.
        if (path_.closed() && delta < -1e-6) delta += len;
        if (delta > 0.0) {
          advanced_m_ += delta;
          s_m_ = p.s_m;
        }
      }
    }
  }
  started_ = true;

  if (s.following) {
    sum_sq_ct_ += cross_track * cross_track;
    max_ct_ = std::max(max_ct_, cross_track);
    ++following_ticks_;
  }

  // Stopped on an end mark while in END: keep the latest distance while this holds.
  const double speed = std::hypot(s.vx_mps, s.vy_mps);
  if (s.in_end_state && std::isfinite(speed) && speed < kStoppedSpeedMps &&
      std::isfinite(s.wz_radps) && std::abs(s.wz_radps) < kStoppedWzRadps) {
    bool near = false;
    double best = 0.0;
    for (const Vec2& c : end_marks_) {
      const double d = dist(q, c);
      if (d <= kEndRadiusM && (!near || d < best)) {
        best = d;
        near = true;
      }
    }
    if (near) end_error_m_ = best;
  }
  return cross_track;
}

// Path distance still to go, in order, before the run has covered the whole reference path:
// a loop's length less the advance (one lap); the open path's end less the arc position.
double RunMetrics::remaining_m() const {
  if (path_.empty() || !started_) return path_.length_m();
  const double len = path_.length_m();
  return path_.closed() ? std::max(0.0, len - advanced_m_) : std::max(0.0, len - s_m_);
}

// Progress, [0, 1]: closed path: advance / L; open path: advance / (L - s0), s0 being where the
// robot first projected onto it. Counts as complete when less than 5 cm is left in order, or
// when the robot has stopped on the end mark (end_reached) with less than the end-mark radius
// (0.25 m) + 5 cm left: the mark may sit a little short of the tape's end.
// Nothing driven along the route is no progress, wherever the robot stands (at the open path's
// end, a few centimetres short of it): a robot that never leaves START scores 0.
double RunMetrics::progress() const {
  if (path_.empty() || !started_ || !(advanced_m_ > 0.0)) return 0.0;
  const double remaining = remaining_m();
  if (remaining < kDoneRemainingM) return 1.0;
  if (end_reached() && remaining < kEndRadiusM + kDoneRemainingM) return 1.0;
  const double len = path_.length_m();
  const double denom = path_.closed() ? len : len - s0_m_;
  if (!(denom > 0.0)) return 1.0;  // drove onto the open path at its very end
  return std::clamp(advanced_m_ / denom, 0.0, 1.0);
}

// Whole loops travelled in order; the 1e-9 absorbs rounding right at a lap boundary.
int RunMetrics::laps() const {
  if (path_.empty() || !path_.closed() || !started_) return 0;
  return static_cast<int>(std::floor(advanced_m_ / path_.length_m() + 1e-9));
}

double RunMetrics::cross_track_rms_m() const {
  if (following_ticks_ == 0) return 0.0;
  return std::sqrt(sum_sq_ct_ / static_cast<double>(following_ticks_));
}

double RunMetrics::cross_track_max_m() const {
  return following_ticks_ == 0 ? 0.0 : max_ct_;
}

double RunMetrics::mean_speed_mps() const {
  const double elapsed = last_t_s_ - first_t_s_;
  return elapsed > 0.0 ? path_length_m_ / elapsed : 0.0;
}

}  // namespace carril::sim
