#include "firmware/behavior/LineBehavior.hpp"

#include "firmware/core/Param.hpp"

#include <cmath>

namespace carril::fw {

LineBehavior::LineBehavior(const BehaviorConfig& cfg, LineController& line,
                           const BypassPlanner& planner, bool holonomic)
    : cfg_(cfg),
      line_(line),
      planner_(planner),
      path_(PathTrackerConfig{2.0, cfg.search_yaw_rate_radps, 0.04}, holonomic) {}

void LineBehavior::enter(LineState s, Phase phase, double t_s) {
  state_ = s;
  no_track_since_s_ = -1.0;  // the pid grace period belongs to one stay in FOLLOW
  since_s_ = t_s;
  set_phase(phase);
}

void LineBehavior::set_phase(Phase phase) {
  if (phase != phase_) {
    phase_ = phase;
    phase_changed_ = true;
  }
}

const char* LineBehavior::take_phase_change() {
  if (!phase_changed_) return nullptr;
  phase_changed_ = false;
  return phase_name(phase_);
}

void LineBehavior::begin(double t_s, double yaw) {
  started_ = true;
  since_s_ = t_s;
  last_yaw_ = yaw;
}

BehaviorOutput LineBehavior::step(const BehaviorInput& in, double dt) {
  if (!started_) begin(in.t_s, in.odom.yaw);
  if (in.fresh_frame) frames_without_line_ = in.line_visible ? 0 : frames_without_line_ + 1;
  if (in.fresh_frame && in.line_visible) {
    line_seen_s_ = in.t_s;
    line_seen_at_ = Vec2(in.odom.x, in.odom.y);
  }
  // Accumulated turning, for the searches.
  turned_ += std::fabs(wrap_angle(in.odom.yaw - last_yaw_));
  last_yaw_ = in.odom.yaw;

  switch (state_) {
    case LineState::Start:
      return start(in);
    case LineState::Follow:
      return follow(in, dt);
    case LineState::Search:
      return search(in);
    case LineState::Avoid:
      return avoid(in);
    case LineState::End:
      return end(in);
    case LineState::Fault:
    case LineState::Count:
      break;
  }
  return {};
}

BehaviorOutput LineBehavior::start(const BehaviorInput& in) {
  BehaviorOutput out;
  if (phase_ == Phase::Wait) {
    if (in.drives_ready && in.camera_ready && in.scanner_ready && in.imu_ready) {
      set_phase(Phase::Find);
      turned_ = 0.0;
    } else if (in.t_s - since_s_ > cfg_.init_timeout_s) {
      out.fault = !in.drives_ready    ? Fault::DriveEnableTimeout
                  : !in.camera_ready  ? Fault::CameraTimeout
                  : !in.scanner_ready ? Fault::ScannerTimeout
                                      : Fault::ImuTimeout;
      enter(LineState::Fault, Phase::Stopped, in.t_s);
    }
    return out;
  }
  if (phase_ == Phase::Find) {
    if (in.fresh_frame && in.line_visible) {
      // On the tape already (it runs out of the bottom of the view, roughly ahead): follow it.
      if (std::fabs(in.line_near.y()) < cfg_.start_on_tape_lateral_m &&
          std::fabs(in.line_near_angle) < cfg_.start_on_tape_angle_rad) {
        line_.reset();
        enter(LineState::Follow, Phase::Track, in.t_s);
        return out;
      }
      start_target_ = to_world(in.odom, in.line_near);
      align_heading_ = in.odom.yaw + in.line_near_angle;
      set_phase(Phase::Approach);
    } else if (turned_ > cfg_.start_max_turn_rad) {
      out.fault = Fault::LineNotFound;
      enter(LineState::Fault, Phase::Stopped, in.t_s);
    } else {
      out.twist.wz = cfg_.search_yaw_rate_radps;  // turn on the spot, looking for tape
    }
    return out;
  }
  if (phase_ == Phase::Approach) {
    // Drive to the nearest tape point that was in view, holding the tape's heading there.
    bool reached = false;
    out.twist = path_.drive_to(in.odom, start_target_, align_heading_, 0.2, reached);
    if (reached) set_phase(Phase::Align);
    return out;
  }
  // align: face along the tape, then follow it.
  if (std::fabs(wrap_angle(align_heading_ - in.odom.yaw)) > cfg_.align_tolerance_rad) {
    out.twist = path_.turn_to(in.odom, align_heading_);
    return out;
  }
  line_.reset();
  enter(LineState::Follow, Phase::Track, in.t_s);
  return out;
}

void LineBehavior::begin_search(const BehaviorInput& in) {
  ++line_lost_;
  search_origin_yaw_ = in.odom.yaw;
  // Kept for the search: the map itself is cleared, then refilled by whatever comes into view.
  lost_path_.clear();
  if (in.tape != nullptr) {
    for (const Vec2& p : in.tape->points()) lost_path_.push_back(p);
  }
  line_.reset();
  enter(LineState::Search, Phase::Left, in.t_s);
}

BehaviorOutput LineBehavior::follow(const BehaviorInput& in, double dt) {
  BehaviorOutput out;
  if (in.obstacle_ahead) {
    // Pass along the line of the tape where it runs into the obstacle: just after a curve that
    // differs from the direction under the robot (where the thesis's line_priority failed).
    if (in.tape_far_valid) {
      align_heading_ = in.tape_far_heading;
      align_point_ = in.tape_far_point;
    } else {
      align_heading_ = in.track.valid ? in.track.tape_heading_odom : in.odom.yaw;
      align_point_ = to_world(in.odom, Vec2(0.0, in.track.valid ? in.track.lateral_m : 0.0));
    }
    excluded_side_ = 0;
    enter(LineState::Avoid, Phase::Stop, in.t_s);
    return out;  // zero twist: brake
  }
  if (in.end_known && (in.end_odom - Vec2(in.odom.x, in.odom.y)).norm() < cfg_.end_approach_m) {
    enter(LineState::End, Phase::Approach, in.t_s);
    return end(in);
  }
  // Memory is left while there is tape ahead, or while the robot is still turning onto the last
  // remembered leg (a corner whose new leg is out of the camera's view while it turns).
  const bool trusted = in.t_s - line_seen_s_ < cfg_.memory_trust_s &&
                       (Vec2(in.odom.x, in.odom.y) - line_seen_at_).norm() < cfg_.memory_trust_m;
  const bool memory_left =
      in.track.valid && trusted &&
      (in.track.remaining_m > 0.05 || std::fabs(in.track.heading_err_rad) > 0.1);
  if (memory_left) {
    no_track_since_s_ = -1.0;
    out.twist = line_.follow(in.track, dt);
    return out;
  }
  if (frames_without_line_ < cfg_.lost_frames) return out;  // wait for the next frames
  // Tape gone: pid first turns toward the last error (the thesis's saturated error) for a moment.
  if (no_track_since_s_ < 0) no_track_since_s_ = in.t_s;
  if (line_.config().strategy == Strategy::Pid &&
      in.t_s - no_track_since_s_ < cfg_.pid_lost_grace_s) {
    out.twist = line_.lost(dt);
    return out;
  }
  no_track_since_s_ = -1.0;
  if (end_within_reach(in)) {
    enter(LineState::End, Phase::Approach, in.t_s);
    return end(in);
  }
  const Vec2 here(in.odom.x, in.odom.y);
  if (!in.end_known && in.end_glimpsed && !reveal_tried_ &&
      (in.end_glimpse_odom - here).norm() < cfg_.end_reveal_m) {
    reveal_tried_ = true;
    reveal_from_ = here;
    enter(LineState::End, Phase::Reveal, in.t_s);
    return end(in);
  }
  begin_search(in);
  out.clear_map = true;
  return out;
}

bool LineBehavior::sighting_runs_backwards(const BehaviorInput& in) const {
  if (lost_path_.size() < 2) return false;
  // The nearest visible tape point and its direction (near to far), odometry frame.
  const Vec2 p = to_world(in.odom, in.line_near);
  const Vec2 dir(std::cos(in.odom.yaw + in.line_near_angle),
                 std::sin(in.odom.yaw + in.line_near_angle));
  double best = cfg_.reacquire_on_path_m * cfg_.reacquire_on_path_m;
  bool on_path = false;
  Vec2 path_dir = Vec2::Zero();
  for (std::size_t i = 0; i + 1 < lost_path_.size(); ++i) {
    const Vec2 a = lost_path_[i], d = lost_path_[i + 1] - a;
    const double len2 = d.squaredNorm();
    if (len2 < 1e-12) continue;
    const double u = clampd((p - a).dot(d) / len2, 0.0, 1.0);
    const double dist2 = (a + u * d - p).squaredNorm();
    if (dist2 <= best) {
      best = dist2;
      on_path = true;
      path_dir = d;
    }
  }
  // New tape (beyond what was remembered) has no direction to disagree with.
  return on_path && dir.dot(path_dir) < 0.0;
}

bool LineBehavior::end_within_reach(const BehaviorInput& in) const {
  return in.end_known && (in.end_odom - Vec2(in.odom.x, in.odom.y)).norm() < cfg_.end_reach_m;
}

BehaviorOutput LineBehavior::search(const BehaviorInput& in) {
  BehaviorOutput out;
  if (end_within_reach(in)) {
    enter(LineState::End, Phase::Approach, in.t_s);
    return end(in);
  }
  if (in.fresh_frame && in.line_visible && in.track.valid && sighting_runs_backwards(in)) {
    // The tape already travelled, seen from the far side after turning round: following it
    // would drive the course backwards. Keep searching.
    ++reversed_sightings_;
    out.clear_map = true;
  } else if (in.fresh_frame && in.line_visible && in.track.valid) {
    ++line_reacquired_;
    line_.reset();
    enter(LineState::Follow, Phase::Track, in.t_s);
    return out;
  }
  // The thesis's search: up to 90 deg left; then 180 deg right; then 90 deg more, heading back.
  const double rel = wrap_angle(in.odom.yaw - search_origin_yaw_);
  const double tol = cfg_.align_tolerance_rad;
  if (phase_ == Phase::Left) {
    if (rel >= kPi / 2 - tol) {
      set_phase(Phase::Right);
    } else {
      out.twist.wz = cfg_.search_yaw_rate_radps;
      return out;
    }
  }
  if (phase_ == Phase::Right) {
    if (rel <= -kPi / 2 + tol && rel < 0) {
      set_phase(Phase::Back);
    } else {
      out.twist.wz = -cfg_.search_yaw_rate_radps;
      return out;
    }
  }
  // back: turn right until heading the way the robot came (origin - 180 deg).
  if (std::fabs(wrap_angle(in.odom.yaw - (search_origin_yaw_ + kPi))) < tol) {
    out.fault = Fault::LineNotFound;
    enter(LineState::Fault, Phase::Stopped, in.t_s);
    return out;
  }
  out.twist.wz = -cfg_.search_yaw_rate_radps;
  return out;
}

BehaviorOutput LineBehavior::avoid(const BehaviorInput& in) {
  BehaviorOutput out;
  const Phase p = phase_;
  if (p == Phase::Stop) {
    const bool still = std::fabs(in.measured.vx) < 0.02 && std::fabs(in.measured.vy) < 0.02 &&
                       std::fabs(in.measured.wz) < 0.05;
    if (still) set_phase(Phase::Align);
    return out;
  }
  if (p == Phase::Align) {
    if (std::fabs(wrap_angle(align_heading_ - in.odom.yaw)) > cfg_.align_tolerance_rad) {
      out.twist = path_.turn_to(in.odom, align_heading_);
      return out;
    }
    // Plan on the newest scan (taken after the robot stopped turning, or close enough).
    plan_ = planner_.plan(*in.obstacles, in.odom, align_point_, align_heading_, in.costmap,
                          excluded_side_);
    if (plan_.blocked) {
      out.fault = Fault::PathBlocked;
      enter(LineState::Fault, Phase::Stopped, in.t_s);
      return out;
    }
    if (!plan_.ok) {  // nothing ahead any more
      enter(LineState::Follow, Phase::Track, in.t_s);
      return out;
    }
    waypoint_ = 0;
    blocked_since_s_ = -1.0;
    // Where the robot stands now, on the tape: a lane found blocked later backs out to here.
    back_out_.clear();
    back_out_.push_back(plan_.waypoints[0]);
    back_out_.push_back(Vec2(in.odom.x, in.odom.y));
    set_phase(Phase::Bypass);
    return out;
  }
  if (p == Phase::BackOut) {
    bool done = false;
    out.twist = path_.follow(in.odom, back_out_.begin(), back_out_.size(), back_out_index_,
                             plan_.heading, cfg_.avoid.speed_mps, done);
    if (done) set_phase(Phase::Align);  // face along the tape again, then plan the other side
    return out;
  }
  if (p == Phase::Bypass) {
    if (in.fresh_scan && waypoint_ <= 1) planner_.refine(*in.obstacles, plan_, in.costmap);
    // The costmap closes the lane ahead (the far side, now seen, meets a wall, or something
    // stands in the lane beyond what was seen at first): back out and try the other side, once,
    // while the robot is short of the obstacle's far end; otherwise stop here.
    if (in.costmap != nullptr && in.costmap_updated &&
        !planner_.lane_clear(plan_, in.odom, waypoint_, *in.costmap)) {
      const Vec2 along(std::cos(plan_.heading), std::sin(plan_.heading));
      const double x_robot = (Vec2(in.odom.x, in.odom.y) - plan_.origin).dot(along);
      if (excluded_side_ == 0 && waypoint_ <= 1 && x_robot < plan_.x_far) {
        excluded_side_ = plan_.side;
        // Still on the way to the lane: straight back to the tape; in it: along it first.
        back_out_index_ = waypoint_ == 0 ? 1 : 0;
        set_phase(Phase::BackOut);
        return out;
      }
      out.fault = Fault::PathBlocked;
      enter(LineState::Fault, Phase::Stopped, in.t_s);
      return out;
    }
    // Something right against the body: stop, and give up if it stays.
    if (in.obstacles->clearance_m(in.odom) < cfg_.avoid.emergency_m) {
      if (blocked_since_s_ < 0) blocked_since_s_ = in.t_s;
      if (in.t_s - blocked_since_s_ > cfg_.avoid.blocked_timeout_s) {
        out.fault = Fault::PathBlocked;
        enter(LineState::Fault, Phase::Stopped, in.t_s);
      }
      return out;
    }
    blocked_since_s_ = -1.0;
    bool done = false;
    out.twist = path_.follow(in.odom, plan_.waypoints.begin(), plan_.waypoints.size(), waypoint_,
                             plan_.heading, cfg_.avoid.speed_mps, done);
    if (done) set_phase(Phase::Rejoin);
    return out;
  }
  // rejoin: face along the tape again, then follow what the camera sees from here.
  if (std::fabs(wrap_angle(plan_.heading - in.odom.yaw)) > cfg_.align_tolerance_rad) {
    out.twist = path_.turn_to(in.odom, plan_.heading);
    return out;
  }
  out.clear_map = true;
  out.rejoined = true;
  ++obstacles_avoided_;
  line_.reset();
  frames_without_line_ = 0;
  enter(LineState::Follow, Phase::Track, in.t_s);
  return out;
}

BehaviorOutput LineBehavior::end(const BehaviorInput& in) {
  BehaviorOutput out;
  if (end_done_) return out;
  if (phase_ == Phase::Reveal) {
    // Straight back over the ground just driven, until the mark is wholly in view.
    if (!in.end_known) {
      if ((Vec2(in.odom.x, in.odom.y) - reveal_from_).norm() >= cfg_.end_reveal_m) {
        begin_search(in);  // not there after all: what the tape's end would have done
        out.clear_map = true;
        return out;
      }
      out.twist.vx = -cfg_.end_speed_mps;
      return out;
    }
    set_phase(Phase::Approach);
  }
  // Stop on the mark: within tolerance, or (differential) once it is beside or behind the centre.
  bool arrived = false;
  out.twist = path_.approach(in.odom, in.end_odom, cfg_.end_speed_mps, cfg_.end_gain,
                             cfg_.end_tolerance_m, arrived);
  if (arrived) {
    end_done_ = true;
    set_phase(Phase::Stopped);
  }
  return out;
}

}  // namespace carril::fw

namespace carril::fw {

std::span<const Param<BehaviorConfig>> BehaviorConfig::params() {
  using C = BehaviorConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, init_timeout_s, "s", 0.1, 60.0, "drives and sensors must be up by then"),
      CARRIL_PARAM(C, search_yaw_rate_radps, "rad/s", 0.05, 5.0, "turning speed while searching"),
      CARRIL_PARAM(C, start_max_turn_rad, "rad", 0.5, 20.0,
                   "START gives up after this much turning without tape"),
      CARRIL_PARAM(C, lost_frames, "frames", 1, 100, "frames without tape before the tape is lost"),
      CARRIL_PARAM(C, memory_trust_m, "m", 0.05, 10.0,
                   "remembered tape unconfirmed over this distance is not trusted"),
      CARRIL_PARAM(C, memory_trust_s, "s", 0.1, 100.0, "... or this long"),
      CARRIL_PARAM(C, pid_lost_grace_s, "s", 0.0, 10.0,
                   "pid turns toward the last error this long first"),
      CARRIL_PARAM(C, end_approach_m, "m", 0.05, 5.0, "END when the mark is this close"),
      CARRIL_PARAM(C, end_speed_mps, "m/s", 0.01, 2.0, "approach speed onto the mark"),
      CARRIL_PARAM(C, end_gain, "1/s", 0.1, 20.0, "approach speed per metre to the mark"),
      CARRIL_PARAM(C, end_tolerance_m, "m", 0.0005, 0.5, "stop this close to the mark"),
      CARRIL_PARAM(C, align_tolerance_rad, "rad", 0.001, 0.5, "heading alignment done within this"),
      CARRIL_PARAM(C, start_on_tape_lateral_m, "m", 0.0, 1.0,
                   "visible tape this close to the centre line ..."),
      CARRIL_PARAM(C, start_on_tape_angle_rad, "rad", 0.0, 1.6,
                   "... and this well aligned: already on the tape"),
      CARRIL_PARAM(C, reacquire_on_path_m, "m", 0.0, 5.0,
                   "tape seen this close to the lost tape is that tape"),
      CARRIL_PARAM(C, end_reach_m, "m", 0.0, 20.0,
                   "a known end mark this close where the tape runs out is the end"),
      CARRIL_PARAM(C, end_reveal_m, "m", 0.0, 5.0,
                   "no end mark known, but one glimpsed cut by the image edge this close where the "
                   "tape runs out: back up at most this far (once) to see it whole"),
  };
  return kParams;
}

Status BehaviorConfig::validate() const {
  return Checks("behavior").params(*this, params()).nested(avoid.validate()).result();
}

}  // namespace carril::fw
