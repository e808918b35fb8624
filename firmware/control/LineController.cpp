#include "firmware/control/LineController.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

LineController::LineController(const StrategyConfig& cfg, bool holonomic)
    : cfg_(cfg), holonomic_(holonomic) {}

void LineController::reset() {
  integral_ = 0.0;
  have_last_ = false;
}

double LineController::corner_speed(const TrackState& t) const {
  double v = cfg_.speed_mps;
  // Curves: keep the lateral acceleration modest (v^2 * kappa <= 0.35 m/s^2).
  const double k = std::fabs(t.curvature_ahead);
  if (k > 1e-3) v = std::min(v, std::sqrt(0.35 / k));
  // Sharp corners: come down to the corner speed by the time the robot reaches it.
  if (std::fabs(t.corner_turn_rad) > cfg_.corner_turn_rad) {
    const double f = clampd(t.corner_dist_m / cfg_.corner_slow_m, 0.0, 1.0);
    v = std::min(v, cfg_.corner_min_speed_mps + f * (cfg_.speed_mps - cfg_.corner_min_speed_mps));
  }
  // Do not run past the end of what has been seen.
  v = std::min(v, std::max(0.0, 1.2 * t.remaining_m));
  return v;
}

Twist LineController::pivot_or(const TrackState& t, const Twist& moving) const {
  // Past a corner the tape leaves at a large angle: turn toward it on the spot, then go on.
  if (std::fabs(t.heading_err_rad) > cfg_.pivot_heading_rad && !holonomic_) {
    return {0.0, 0.0,
            clampd(cfg_.heading_gain * t.heading_err_rad, -cfg_.max_yaw_rate_radps,
                   cfg_.max_yaw_rate_radps)};
  }
  return moving;
}

Twist LineController::marks(const TrackState& t) {
  const double v = corner_speed(t);
  const double d = t.lookahead.norm();
  const double bearing = std::atan2(t.lookahead.y(), t.lookahead.x());
  Twist out;
  out.vx = v * std::max(0.0, std::cos(bearing));
  // Pure pursuit: the arc through the look-ahead point, plus the tape's own curvature.
  out.wz = d > 1e-3 ? 2.0 * out.vx * std::sin(bearing) / d : 0.0;
  if (out.vx < 0.05) out.wz = cfg_.heading_gain * bearing;
  if (holonomic_) {
    // Mecanum: also close the lateral offset directly, so corners are not cut.
    out.vy = clampd(cfg_.lp_k_lateral * t.lateral_m, -v, v);
  }
  out.wz = clampd(out.wz, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
  return pivot_or(t, out);
}

Twist LineController::line_priority(const TrackState& t) {
  const double v = corner_speed(t);
  const double th = t.heading_err_rad;
  Twist out;
  // Move along the tape's direction (seen from the robot), with the lateral offset corrected
  // across it: staying on the line has priority over facing along it.
  const double lat = clampd(cfg_.lp_k_lateral * t.lateral_m, -0.5, 0.5);
  out.vx = v * std::cos(th) - lat * std::sin(th);
  out.vy = v * std::sin(th) + lat * std::cos(th);
  out.wz = cfg_.lp_k_angle * th - cfg_.lp_k_lateral_w * t.lateral_m + v * t.curvature_ahead;
  out.wz = clampd(out.wz, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
  return out;
}

Twist LineController::pid(const TrackState& t, double dt) {
  // Error: the tape's lateral offset at the look-ahead point, normalised to [-1, 1].
  const double e = clampd(t.lookahead.y() / cfg_.pid_error_scale_m, -1.0, 1.0);
  const bool curve = std::fabs(e) > cfg_.pid_curve_threshold;
  const PidGains& g = curve ? cfg_.pid_curve : cfg_.pid_straight;
  integral_ = clampd(integral_ + e * dt, -1.0, 1.0);
  const double de = have_last_ && dt > 0 ? (e - last_error_) / dt : 0.0;
  last_error_ = e;
  have_last_ = true;
  Twist out;
  out.wz = clampd(g.kp * e + g.ki * integral_ + g.kd * de, -cfg_.max_yaw_rate_radps,
                  cfg_.max_yaw_rate_radps);
  const double v_max = std::min(g.speed_mps, corner_speed(t));
  out.vx = curve ? v_max / (std::fabs(out.wz) + 1.0) : v_max;
  return pivot_or(t, out);
}

Twist LineController::follow(const TrackState& t, double dt_s) {
  // At the end of the remembered tape with the tape leaving at an angle (a corner whose new leg
  // is below the camera's view): turn on the spot onto the remembered leg, whatever the strategy.
  if (t.remaining_m < 0.15 && std::fabs(t.heading_err_rad) > 0.1) {
    return {0.0, 0.0,
            clampd(cfg_.heading_gain * t.heading_err_rad, -cfg_.max_yaw_rate_radps,
                   cfg_.max_yaw_rate_radps)};
  }
  switch (cfg_.strategy) {
    case Strategy::Marks:
      return marks(t);
    case Strategy::LinePriority:
      return line_priority(t);
    case Strategy::Pid:
      return pid(t, dt_s);
  }
  return {};
}

Twist LineController::lost(double /*dt_s*/) {
  if (cfg_.strategy != Strategy::Pid || !have_last_) return {};
  // The thesis's rule: with no tape the error is +-1 with the sign of the last error, so the
  // robot turns (slowly) toward the side the tape left from.
  const double e = last_error_ >= 0 ? 1.0 : -1.0;
  const double w = clampd(cfg_.pid_curve.kp * e, -cfg_.max_yaw_rate_radps, cfg_.max_yaw_rate_radps);
  return {cfg_.pid_curve.speed_mps / (std::fabs(w) + 1.0) * 0.3, 0.0, w};
}

}  // namespace carril::fw

namespace carril::fw {

std::span<const Param<StrategyConfig>> StrategyConfig::params() {
  using C = StrategyConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, speed_mps, "m/s", 0.01, 5.0, "cruise speed: the mission's speed_mps", nullptr,
                   false),
      CARRIL_PARAM(C, marks_lookahead_m, "m", 0.01, 5.0, "marks: look-ahead point on the tape"),
      CARRIL_PARAM(C, lp_k_lateral, "1/s", 0.0, 50.0,
                   "line_priority: lateral speed per metre of offset"),
      CARRIL_PARAM(C, lp_k_angle, "1/s", 0.0, 50.0,
                   "line_priority: yaw rate per radian of tape angle"),
      CARRIL_PARAM(C, lp_k_lateral_w, "rad/s per m", -50.0, 50.0,
                   "line_priority: yaw rate per metre of offset subtracted"),
      CARRIL_PARAM(C, pid_lookahead_m, "m", 0.0, 5.0,
                   "pid: the error is the offset this far ahead"),
      CARRIL_PARAM(C, pid_error_scale_m, "m", 0.01, 5.0, "pid: offset that counts as error 1"),
      CARRIL_PARAM(C, pid_curve_threshold, "(error)", 0.0, 1.0,
                   "pid: above this the curve gains apply"),
      CARRIL_PARAM(C, heading_gain, "1/s", 0.0, 50.0,
                   "marks, pid: yaw rate per radian of heading error"),
      CARRIL_PARAM(C, corner_turn_rad, "rad", 0.05, 3.2,
                   "a sharper turn within the preview is a corner"),
      CARRIL_PARAM(C, corner_slow_m, "m", 0.0, 10.0, "start slowing this far before a corner"),
      CARRIL_PARAM(C, corner_min_speed_mps, "m/s", 0.0, 5.0, "speed at the corner"),
      CARRIL_PARAM(C, pivot_heading_rad, "rad", 0.05, 3.2,
                   "heading error above this: turn on the spot"),
      CARRIL_PARAM(C, max_yaw_rate_radps, "rad/s", 0.05, 20.0, "the followers' yaw-rate cap"),
  };
  return kParams;
}

std::span<const Param<PidGains>> PidGains::params() {
  using C = PidGains;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, kp, "rad/s per unit error", 0.0, 100.0,
                   "pid: proportional gain (pid_straight on straights, pid_curve in curves)"),
      CARRIL_PARAM(C, ki, "rad/s per unit error s", 0.0, 100.0, "pid: integral gain"),
      CARRIL_PARAM(C, kd, "rad s/s per unit error", 0.0, 100.0, "pid: derivative gain"),
      CARRIL_PARAM(C, speed_mps, "m/s", 0.0, 5.0,
                   "pid: top speed on straights (pid_straight) or in curves (pid_curve)",
                   "the mission's `speed_mps` (pid_curve: 0.8 x)"),
  };
  return kParams;
}

Status StrategyConfig::validate() const {
  return Checks("strategy")
      .params(*this, params())
      .nested(Checks("strategy.pid_straight").params(pid_straight, PidGains::params()).result())
      .nested(Checks("strategy.pid_curve").params(pid_curve, PidGains::params()).result())
      .result();
}

}  // namespace carril::fw
