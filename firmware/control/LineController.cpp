#include "firmware/control/LineController.hpp"

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

Status StrategyConfig::validate() const {
  Checks c("strategy");
  const PidGains* sets[] = {&pid_straight, &pid_curve};
  for (const PidGains* g : sets) {
    const char* which = g == &pid_straight ? "pid_straight" : "pid_curve";
    c.range(which, g->speed_mps, 0.0, 5.0, "m/s (speed_mps)")
        .fail_if(!(g->kp >= 0.0 && g->ki >= 0.0 && g->kd >= 0.0), which,
                 "gains kp, ki, kd must be >= 0");
  }
  return c.range("speed_mps", speed_mps, 0.01, 5.0, "m/s")
      .range("marks_lookahead_m", marks_lookahead_m, 0.01, 5.0, "m")
      .range("lp_k_lateral", lp_k_lateral, 0.0, 50.0, "1/s")
      .range("lp_k_angle", lp_k_angle, 0.0, 50.0, "1/s")
      .range("lp_k_lateral_w", lp_k_lateral_w, -50.0, 50.0, "rad/s per m")
      .range("pid_lookahead_m", pid_lookahead_m, 0.0, 5.0, "m")
      .range("pid_error_scale_m", pid_error_scale_m, 0.01, 5.0, "m")
      .range("pid_curve_threshold", pid_curve_threshold, 0.0, 1.0, "(normalised error)")
      .range("heading_gain", heading_gain, 0.0, 50.0, "1/s")
      .range("corner_turn_rad", corner_turn_rad, 0.05, 3.2, "rad")
      .range("corner_slow_m", corner_slow_m, 0.0, 10.0, "m")
      .range("corner_min_speed_mps", corner_min_speed_mps, 0.0, 5.0, "m/s")
      .range("pivot_heading_rad", pivot_heading_rad, 0.05, 3.2, "rad")
      .range("max_yaw_rate_radps", max_yaw_rate_radps, 0.05, 20.0, "rad/s")
      .result();
}

}  // namespace carril::fw
