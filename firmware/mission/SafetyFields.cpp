#include "firmware/mission/SafetyFields.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

namespace {

// The positive root v of v^2 / (2 a) + b v + c = 0 (0 when c >= 0: no speed fits).
double root(double a, double b, double c) {
  if (c >= 0.0) return 0.0;
  return a * (-b + std::sqrt(b * b - 2.0 * c / a));
}

// A path whose radius is at least this many band half-widths counts as straight.
constexpr double kStraightWidths = 4.0;

}  // namespace

std::span<const Param<SafetyFieldsConfig>> SafetyFieldsConfig::params() {
  using C = SafetyFieldsConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, scan_period_s, "s", 0.0, 1.0,
                   "part of the reaction time: a scan period (the lidar's rate)", nullptr, false),
      CARRIL_PARAM(C, tick_s, "s", 0.0, 1.0,
                   "part of the reaction time: a control tick (the loop's rate)", nullptr, false),
      CARRIL_PARAM(C, drive_latency_s, "s", 0.0, 1.0,
                   "a command leaving the loop to the drive acting on it; with a scan period and a "
                   "tick it is the reaction time T"),
      CARRIL_PARAM(C, decel_mps2, "m/s^2", 0.01, 20.0,
                   "the deceleration of a stop: limits.max_accel_mps2", nullptr, false),
      CARRIL_PARAM(C, margin_m, "m", 0.0, 2.0,
                   "C, added to every stopping distance of the protective and warning fields"),
      CARRIL_PARAM(C, static_margin_m, "m", 0.0, 2.0,
                   "what a stop short of a static return (a wall, a standing box) keeps from it"),
      CARRIL_PARAM(C, side_margin_m, "m", 0.0, 1.0,
                   "the protective band beyond the body's sides, across the direction of travel"),
      CARRIL_PARAM(C, approach_speed_mps, "m/s", 0.0, 5.0,
                   "K, how fast something moving may approach (ISO 13855's walking speed)"),
      CARRIL_PARAM(C, blind_speed_mps, "m/s", 0.0, 5.0,
                   "the speed cap in a direction the lidar does not see (behind a front lidar)"),
      CARRIL_PARAM(C, max_field_m, "m", 0.0, 100.0,
                   "the longest protective field allowed (a safety scanner's largest field); 0: "
                   "only the lidar's reliable range limits it"),
  };
  return kParams;
}

Status SafetyFieldsConfig::validate() const {
  return Checks("runner.fields").params(*this, params()).result();
}

double SafetyFieldsConfig::stop_m(double v) const {
  return v * reaction_s() + v * v / (2.0 * decel_mps2) + margin_m;
}

double SafetyFieldsConfig::stop_time_s(double v) const {
  return reaction_s() + v / decel_mps2;
}

double SafetyFieldsConfig::warning_m(double v) const {
  return stop_m(v) + approach_speed_mps * stop_time_s(v);
}

double SafetyFieldsConfig::warning_side_m(double v) const {
  return side_margin_m + approach_speed_mps * stop_time_s(v);
}

double SafetyFieldsConfig::static_stop_m(double v) const {
  return v * reaction_s() + v * v / (2.0 * decel_mps2) + static_margin_m;
}

double SafetyFieldsConfig::static_cap_mps(double d) const {
  return root(decel_mps2, 2.0 * reaction_s(), static_margin_m - d);
}

double SafetyFieldsConfig::warning_cap_mps(double d) const {
  const double k = approach_speed_mps;
  return root(decel_mps2, reaction_s() + k / decel_mps2, margin_m + k * reaction_s() - d);
}

double SafetyFieldsConfig::side_cap_mps(double l) const {
  const double k = approach_speed_mps;
  if (k <= 0.0) return l > side_margin_m ? 1e9 : 0.0;
  return std::max(0.0, decel_mps2 * ((l - side_margin_m) / k - reaction_s()));
}

FieldVerdict SafetyFields::check(const ObstacleField& f, const Pose2& pose, const Twist& want,
                                 double v_now) const {
  FieldVerdict out;
  const double v_req = std::hypot(want.vx, want.vy);
  out.allowed_mps = v_req;
  if (!cfg_.enabled || v_req < 1e-6 || !f.valid()) return out;
  // The direction of travel in the body frame, the body's reach along it (its leading edge) and
  // across it (half the band it sweeps).
  const Vec2 u(want.vx / v_req, want.vy / v_req);
  const Vec2 n(-u.y(), u.x());
  const double lead = fp_.half_length_m * std::fabs(u.x()) + fp_.half_width_m * std::fabs(u.y());
  const double half = fp_.half_length_m * std::fabs(u.y()) + fp_.half_width_m * std::fabs(u.x());
  const double v = std::max(v_req, v_now);
  const double stop_now = cfg_.stop_m(v_now);
  const double static_stop_now = cfg_.static_stop_m(v_now);
  // Out of the lidar's view: the far end of the protective field at the faster of the two
  // speeds, or its corners at the leading edge.
  const double reach = lead + cfg_.stop_m(v);
  out.blind = !f.sees(u * reach) || !f.sees(u * (lead + 0.05) + n * half) ||
              !f.sees(u * (lead + 0.05) - n * half);
  double cap = v_req;
  if (out.blind) cap = std::min(cap, cfg_.blind_speed_mps);
  // The band is straight: on a tight arc (radius under a few body widths) the body leaves it, and
  // static returns are the swept-footprint check's to judge along the arc (MotionCheck).
  const double radius_m = std::fabs(want.wz) > 1e-9 ? v_req / std::fabs(want.wz) : 1e9;
  const bool straight = radius_m >= kStraightWidths * (half + cfg_.side_margin_m);
  const PoseFrame frame(pose);
  const double radius = std::min(fp_.half_length_m, fp_.half_width_m);
  const auto judge = [&](const Vec2& w, bool moving) {
    const Vec2 p = frame.to_robot(w);
    const double across = std::fabs(p.dot(n));
    // Ahead of the leading edge [m]: a disc's edge is nearer the centre off its axis.
    const double edge =
        round_ ? std::sqrt(std::fmax(radius * radius - across * across, 0.0)) : lead;
    const double s = p.dot(u) - edge;
    if (s <= 0.0) return;            // beside or behind the body: not in the way
    const double l = across - half;  // beyond the band, across [m]
    // Something moving is judged with the side margin; a static return only in the band the
    // body itself sweeps (the robot may pass a wall closely, not drive into it).
    const bool in_band = l <= (moving ? cfg_.side_margin_m : 0.0);
    if (in_band && (moving || straight) && s < (moving ? stop_now : static_stop_now)) {
      out.protective = true;
    }
    if (moving) {
      const double c = std::max(cfg_.warning_cap_mps(s), cfg_.side_cap_mps(l));
      if (c < cap) {
        cap = c;
        out.warning = true;
      }
    } else if (in_band && straight) {
      const double c = cfg_.static_cap_mps(s);
      if (c < cap) {
        cap = c;
        out.static_cut = true;
      }
    }
  };
  const auto& pts = f.points();
  for (std::size_t i = 0; i < pts.size(); ++i) judge(pts[i], f.moving(i));
  // Returns that left the view still stand where they were (the lidar has not looked past them).
  for (const Vec2& w : f.remembered()) judge(w, false);
  out.allowed_mps = cap;
  if (out.protective) {
    out.scale = 0.0;
  } else if (cap < v_req) {
    out.scale = cap / v_req;
  }
  return out;
}

}  // namespace carril::fw
