#pragma once
// A short memory of the tape in the odometry frame. The camera sees the tape well ahead of the
// robot (0.7 to 1.8 m on campero); remembering those points lets the controllers measure the
// tape where it matters, under the robot's centre, and keep following briefly when the view is
// empty. Each new frame replaces what memory held from its nearest visible tape point on; points
// the robot has left behind are kept until there is no room for newer ones.
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"

namespace carril::fw {

// Where the robot is relative to the remembered tape.
struct TrackState {
  bool valid = false;
  double lateral_m = 0.0;         // tape's offset from the robot centre, + = tape to the left [m]
  double heading_err_rad = 0.0;   // tape heading minus robot heading at the nearest point [rad]
  double curvature_ahead = 0.0;   // mean signed curvature over the next preview distance [1/m]
  Vec2 lookahead = Vec2::Zero();  // point `lookahead_m` further along the tape, robot frame [m]
  double remaining_m = 0.0;       // remembered tape ahead of the nearest point [m]
  // The sharpest turn within the preview distance: where it is and how much it turns.
  double corner_dist_m = 1e9;      // along the tape from the nearest point [m]
  double corner_turn_rad = 0.0;    // signed heading change at it (+ = left)
  double tape_heading_odom = 0.0;  // tape direction at the nearest point, odometry frame [rad]
};

class TapeMap {
 public:
  static constexpr std::size_t kMaxPoints = 160;

  void clear() {
    pts_.clear();
    stale_frames_ = 0;
  }
  bool empty() const { return pts_.size() < 2; }
  std::size_t size() const { return pts_.size(); }

  // New centre-line points (robot frame, near to far) seen from odometry pose `odom`.
  void add(const Pose2& odom, const Vec2* pts_robot, std::size_t n);
  // Tracking quantities for a robot at `odom`.
  TrackState track(const Pose2& odom, double lookahead_m, double preview_m) const;
  // The farthest remembered stretch of tape (at least `span_m` long where it runs straight; only
  // the new leg just past a corner): a point on it and its direction, odometry frame. Where the
  // tape runs under an obstacle, this is its line there.
  bool far_segment(double span_m, Vec2& point, double& heading) const;
  // Points further than this off the chord end a straight stretch (the tape is 5 cm wide; a
  // 1.2 m-radius arc bows 9 mm over 0.3 m) [m].
  static constexpr double kStraightTolM = 0.02;
  // Whether a piece of tape seen from `odom` (centre-line points, robot frame, near to far)
  // continues the remembered tape: at least kMinPieceM long, and either lying on the remembered
  // path (every point within tolerance() of a segment's length, running the path's way there)
  // or reaching past memory's end across a gap of at most kContinueReachM, on a line that passes
  // within tolerance(gap) of the end (kContinueTolM, plus kContinueSpread per metre of gap up to
  // kContinueSpreadUpToM, for a tape that bends) and within kContinueMaxTurnRad of the way
  // memory's last 15 cm ran. `extends`: the latter, so
  // adding the piece tells memory something new.
  bool continues(const Pose2& odom, const Vec2* pts_robot, std::size_t n, bool& extends) const;
  static constexpr double kMinPieceM = 0.04;           // [m]
  static constexpr double kContinueTolM = 0.04;        // [m]
  static constexpr double kContinueReachM = 4.0;       // [m]
  static constexpr double kContinueSpread = 0.05;      // [m per m]
  static constexpr double kContinueMaxTurnRad = 0.6;   // [rad]
  static constexpr double kContinueSpreadUpToM = 0.6;  // the tolerance grows over this much gap
  // The tolerance across a gap of gap_m [m].
  static double tolerance(double gap_m) {
    return kContinueTolM + kContinueSpread * (gap_m < 0.0 ? 0.0
                                              : gap_m < kContinueSpreadUpToM
                                                  ? gap_m
                                                  : kContinueSpreadUpToM);
  }
  // Remembered points, odometry frame, in path order.
  const StaticVector<Vec2, kMaxPoints>& points() const { return pts_; }

 private:
  // The nearest point of the remembered path: segment index and position along it (u < 0 on the
  // first segment: behind the first point).
  struct Nearest {
    std::size_t seg = 0;
    double u = 0.0;
  };
  Nearest nearest(const Vec2& q) const;
  // Behind the first point: the nearest point and heading on the tape continued backwards.
  void continue_behind(const Vec2& q, double seg_len, Vec2& nearest, double& tape_heading) const;
  // Look-ahead point, preview curvature, sharpest corner and remaining length into `t`.
  void walk_ahead(const Nearest& n, const Vec2& nearest, const Vec2& dir, double seg_len,
                  double tape_heading, double lookahead_m, double preview_m, const Pose2& odom,
                  TrackState& t) const;
  double start_curvature() const;
  StaticVector<Vec2, kMaxPoints> pts_;
  int stale_frames_ = 0;  // frames in a row none of whose points could follow memory
};

}  // namespace carril::fw
