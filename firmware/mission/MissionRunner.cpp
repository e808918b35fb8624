#include "firmware/mission/MissionRunner.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

std::span<const Param<MissionRunnerConfig>> MissionRunnerConfig::params() {
  using C = MissionRunnerConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(
          C, blocked_timeout_s, "s", 0.1, 86400.0,
          "a motion the fields or the checks keep stopped this long in a row: `motion_blocked`"),
      CARRIL_PARAM(C, stall_timeout_s, "s", 0.0, 86400.0,
                   "an active mission whose robot has not moved `stall_progress_m` this long, "
                   "while not deliberately waiting: `stalled` (0: never)"),
      CARRIL_PARAM(C, stall_progress_m, "m", 0.01, 10.0, "the distance that counts as progress"),
      CARRIL_PARAM(C, lost_turn_radps, "rad/s", 0.0, 2.0,
                   "unlocalised, turn in place at this rate to show the localiser the room (0: "
                   "stand still); the robot file's localisation section",
                   nullptr, false),
      CARRIL_PARAM(
          C, lost_turn_clearance_m, "m", 0.0, 1.0,
          "turn in place only while every lidar point is this far beyond the circumscribed circle",
          nullptr, false),
      CARRIL_PARAM(C, max_unlocalised_s, "s", 0.0, 86400.0,
                   "held unlocalised this long in a row: `not_localised` (0: wait for ever)",
                   nullptr, false),
  };
  return kParams;
}

Status MissionRunnerConfig::validate() const {
  return Checks("runner")
      .params(*this, params())
      .nested(obstacle.validate())
      .nested(fields.validate())
      .nested(check.validate())
      .nested(lost_explore.validate())
      .result();
}

double MissionRunnerConfig::lost_turn_reach_m(const Footprint& fp) const {
  return lost_turn_radps > 0.0 ? fp.turn_sweep_m() + lost_turn_clearance_m + 0.1 : 0.0;
}

MissionRunner::MissionRunner(const MissionRunnerConfig& cfg, double period_s, int wheel_count,
                             Mission& mission, const Topic<SensorFrame>& frame,
                             const Topic<OdometryMsg>& odom, const Topic<ObstacleField>& obstacles,
                             Topic<MotionRequest>& out, FaultSink& faults, bool imu_present)
    : period_s_(period_s),
      wheel_count_(wheel_count),
      mission_(mission),
      frame_(frame),
      out_(out),
      faults_(faults),
      guard_(cfg.obstacle, cfg.fields, obstacles, odom),
      obstacles_(obstacles),
      odom_(odom),
      lost_turn_radps_(cfg.lost_turn_radps),
      lost_turn_clearance_m_(cfg.lost_turn_clearance_m),
      max_unlocalised_s_(cfg.max_unlocalised_s),
      explorer_(cfg.lost_explore, cfg.lost_turn_radps),
      imu_present_(imu_present),
      fields_(cfg.fields, obstacles.get().footprint(), cfg.check.round_body),
      check_(cfg.check, cfg.fields, obstacles.get().footprint()),
      blocked_timeout_s_(cfg.blocked_timeout_s),
      stall_timeout_s_(cfg.stall_timeout_s),
      stall_progress_m_(cfg.stall_progress_m) {}

MotionRequest MissionRunner::safeguarded(const MotionRequest& want, bool& stopped) {
  stopped = false;
  MotionRequest m = want;
  const Twist& t = odom_.get().twist;
  const FieldVerdict v =
      fields_.check(obstacles_.get(), odom_.get().pose, want.twist, std::hypot(t.vx, t.vy));
  if (v.scale >= 1.0) return m;
  if (v.blind) ++tel_.blind_ticks;
  if (v.scale <= 0.0 || v.protective) {
    ++tel_.field_stops;
    tel_.last_stop = "field";
    tel_.last_stopped = want.twist;
    m.twist = {};
    stopped = true;
    return m;
  }
  ++tel_.field_slowdowns;
  m.twist.vx *= v.scale;
  m.twist.vy *= v.scale;
  m.twist.wz *= v.scale;
  return m;
}

MotionRequest MissionRunner::checked(const MotionRequest& want, bool& stopped) {
  stopped = false;
  const OdometryMsg& odom = odom_.get();
  const Pose2& pose = pose_ != nullptr ? pose_->get().pose : odom.pose;
  const MotionVerdict v = check_.check(want.twist, pose, obstacles_.get(), odom.pose,
                                       std::hypot(odom.twist.vx, odom.twist.vy), odom.twist.wz);
  MotionRequest m = want;
  m.twist = v.twist;
  if (!v.clear) {
    ++tel_.check_stops;
    tel_.last_stop = v.crowded ? "crowded" : v.turn ? "turn" : "path";
    tel_.last_stopped = want.twist;
    stopped = true;
  } else if (v.alternative) {
    ++tel_.check_alternatives;
  } else if (v.scale < 1.0) {
    ++tel_.check_slowdowns;
  }
  return m;
}

bool MissionRunner::blocked_for(bool stopped) {
  blocked_s_ = stopped ? blocked_s_ + period_s_ : 0.0;
  tel_.blocked_max_s = std::max(tel_.blocked_max_s, blocked_s_);
  if (blocked_s_ <= blocked_timeout_s_) return true;
  faults_.raise(Fault::MotionBlocked, 0, mission_.state().name);
  return false;
}

bool MissionRunner::progressing(bool waiting, const char* state) {
  const Pose2& p = odom_.get().pose;
  const Vec2 here(p.x, p.y);
  const MissionStatus st = mission_.state().status;
  const bool busy = st == MissionStatus::Starting || st == MissionStatus::Active ||
                    st == MissionStatus::Finishing;
  if (!anchored_ || waiting || !busy || (here - stall_anchor_).norm() >= stall_progress_m_) {
    stall_anchor_ = here;
    anchored_ = true;
    stall_s_ = 0.0;
    return true;
  }
  stall_s_ += period_s_;
  if (stall_timeout_s_ <= 0.0 || stall_s_ <= stall_timeout_s_) return true;
  faults_.raise(Fault::Stalled, 0, state);
  return false;
}

// The motion while the mission is held: still, or the explorer's turn in place when there is
// room for one and its legs toward open space.
MotionRequest MissionRunner::held() {
  MotionRequest m;
  if (lost_turn_radps_ <= 0.0) return m;
  const ObstacleField& f = obstacles_.get();
  if (!f.valid()) return m;
  const Pose2& pose = odom_.get().pose;
  // The circle the turn sweeps lies this far beyond the rectangle at most (at its corners'
  // sides); clearance_m measures from the rectangle. All round: a corner sweeps the scanner's
  // blind sector too (what it saw there is remembered).
  const bool can_turn =
      f.clearance_all_round_m(pose) >= f.footprint().turn_sweep_m() + lost_turn_clearance_m_;
  // The corridors ahead and behind only where they can lead somewhere: a leg, or backing out of
  // one that ended with no room to turn.
  const double margin = guard_.config().corridor_margin_m;
  const double free_m = explorer_.drives() ? f.ahead_m(pose, margin, 50.0) : 0.0;
  const double behind_m = explorer_.drives() ? f.behind_m(pose, margin, 50.0) : 0.0;
  m.twist = explorer_.step(pose, can_turn, free_m, behind_m);
  return m;
}

void MissionRunner::run() {
  const SensorFrame& f = frame_.get();
  if (faults_.latched()) {
    // Safe stop: the mission is not asked again.
    if (!tel_.stopped) {
      mission_.exit();
      tel_.stopped = true;
    }
    out_.publish(MotionRequest{}, f.now_ns);
    return;
  }
  if (pose_ != nullptr && !pose_->get().localised) {
    ++tel_.unlocalised_ticks;
    unlocalised_s_ += period_s_;
    if (max_unlocalised_s_ > 0.0 && unlocalised_s_ > max_unlocalised_s_) {
      faults_.raise(Fault::NotLocalised, 0, "held");
      out_.publish(MotionRequest{}, f.now_ns);
      return;
    }
    bool stopped = false;
    const MotionRequest m = safeguarded(held(), stopped);
    tel_.lost_legs = explorer_.legs();
    tel_.lost_backs = explorer_.backs();
    if (m.twist.vx != 0.0) {
      ++tel_.lost_drive_ticks;
    } else if (m.twist.wz != 0.0) {
      ++tel_.lost_turn_ticks;
    }
    out_.publish(m, f.now_ns);
    return;
  }
  if (unlocalised_s_ > 0.0) explorer_.reset();
  unlocalised_s_ = 0.0;
  if (pose_ != nullptr && pose_->get().relocalisations != seen_relocalisations_) {
    seen_relocalisations_ = pose_->get().relocalisations;
    ++tel_.relocalisations;
    if (entered_) mission_.relocalised();
  }
  guard_.new_tick();
  MissionContext ctx;
  ctx.t_s = double(f.now_ns) * 1e-9;
  ctx.dt_s = period_s_;
  ctx.drives_ready = drives_enabled(f.wheels, wheel_count_);
  imu_seen_ = imu_seen_ || f.imu.valid;
  ctx.imu_ready = !imu_present_ || imu_seen_;
  ctx.guard = &guard_;
  if (!entered_) {
    mission_.enter(ctx);
    entered_ = true;
  }
  const char* was = mission_.state().name;
  MissionOutput o = mission_.update(ctx);
  if (o.fault != Fault::None) faults_.raise(o.fault, 0, was);
  bool stopped = false;
  if (o.motion.guarded && guard_.ahead() &&
      (o.motion.twist.vx != 0.0 || o.motion.twist.vy != 0.0)) {
    o.motion.twist = {};
    ++tel_.obstacle_stops;
    stopped = true;
  }
  bool cut = false;
  o.motion = safeguarded(o.motion, cut);
  stopped = stopped || cut;
  if (!stopped) {
    o.motion = checked(o.motion, cut);
    stopped = cut;
  }
  if (!blocked_for(stopped) || !progressing(stopped || mission_.state().waiting, was)) {
    out_.publish(MotionRequest{}, f.now_ns);
    return;
  }
  out_.publish(o.motion, f.now_ns);
}

}  // namespace carril::fw
