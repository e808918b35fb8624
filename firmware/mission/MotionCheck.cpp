#include "firmware/mission/MotionCheck.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

namespace {
constexpr double kTurnOnlyMps = 0.05;  // slower than this while turning: a turn on the spot [m/s]
}  // namespace

std::span<const Param<MotionCheckConfig>> MotionCheckConfig::params() {
  using C = MotionCheckConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, pad_m, "m", 0.0, 0.5,
                   "the clearance the swept footprint of every motion keeps from lethal cells and "
                   "returns; what is nearer may come nearer only by grazing (a quarter of the "
                   "travel), never within 1 cm"),
      CARRIL_PARAM(C, turn_margin_rad, "rad", 0.0, 1.0,
                   "a turn on the spot is checked this far past where it could stop"),
      CARRIL_PARAM(C, yaw_decel_radps2, "rad/s^2", 0.01, 50.0,
                   "how fast a turn stops: limits.max_yaw_accel_radps2", nullptr, false),
  };
  return kParams;
}

Status MotionCheckConfig::validate() const {
  return Checks("runner.check").params(*this, params()).result();
}

MotionCheck::MotionCheck(const MotionCheckConfig& cfg, const SafetyFieldsConfig& fields,
                         const Footprint& fp)
    : cfg_(cfg),
      fields_(fields),
      fp_(fp),
      guard_(fp.half_length_m, fp.half_width_m, cfg.pad_m, fp.circumscribed_m()) {
  guard_.set_round(cfg.round_body);
  guard_.set_exact_points(true);
  guard_.set_no_closer(true);
}

MotionVerdict MotionCheck::check(const Twist& want, const Pose2& pose, const ObstacleField& f,
                                 const Pose2& odom_pose, double v_now, double wz_now) {
  MotionVerdict out;
  out.twist = want;
  const double v = std::hypot(want.vx, want.vy);
  const double w = want.wz;
  if (!cfg_.enabled || (v < 1e-6 && std::fabs(w) < 1e-6)) return out;
  out.turn = v < kTurnOnlyMps && std::fabs(w) > 1e-6;
  if (out.turn && cfg_.round_body) return out;  // a disc turning in place sweeps nothing new
  // How far the motion goes before it could stop: a reaction's worth and the braking.
  const double speed = std::max(v, v_now);
  const double reach = fields_.stop_m(speed) - fields_.margin_m + cfg_.pad_m;
  const double wmax = std::max(std::fabs(w), std::fabs(wz_now));
  const double turn = wmax * fields_.reaction_s() + wmax * wmax / (2.0 * cfg_.yaw_decel_radps2) +
                      cfg_.turn_margin_rad;
  guard_.set_radius(fp_.circumscribed_m() + cfg_.pad_m + (out.turn ? 0.1 : reach + 0.1));
  const CostmapView* c = costmap();
  const bool have_map = c != nullptr && c->updates() > 0;
  if (have_map) {
    // What the body can touch: the lidar's marks and the map's walls. The terrain layer (a
    // step, a slope, a trench) is where wheels must not go, which the planners keep to; a body
    // turning above the floor beside it touches nothing.
    guard_.gather(pose, c->obstacles());
    if (const RollingGrid<std::uint8_t>* walls = c->walls()) guard_.add_cells(pose, *walls);
  } else {
    guard_.gather(pose, no_grid_);
  }
  if (f.valid()) {
    // Where the lidar looks now its returns give the surfaces exactly; the costmap's cells (half
    // a cell round an unknown point) hold what it cannot see.
    if (have_map) guard_.keep_cells_if([&](double x, double y) { return !f.sees(Vec2(x, y)); });
    guard_.add_points(f.points().begin(), f.points().size(), odom_pose);
    guard_.add_points(f.remembered().begin(), f.remembered().size(), odom_pose);
  }
  if (guard_.crowded()) {
    ++crowded_;
    out.crowded = true;
    out.clear = false;
    out.twist = Twist{};
    return out;
  }
  if (out.turn) {
    out.clear = guard_.rotation_clear(std::copysign(std::min(turn, 2.0 * kPi), w));
    out.twist = out.clear ? want : Twist{};
    return out;
  }
  // The request first; when it is not clear, the nearest motion that is: less turn (a turn
  // into a wall beside), then a tighter arc at a lower speed, then (a tight turn blocked at its
  // bulge, a lane's U-turn at a wall) the turn on the spot. One that needs no cut in speed is
  // taken before one that does: a U-turn at a wall turns on the spot rather than creep straight.
  double scale = 0.0;
  if (translation(want, reach, scale, out.free_m)) {
    out.scale = scale;
    out.twist = Twist{want.vx * scale, want.vy * scale, want.wz * scale};
    return out;
  }
  out.clear = false;
  out.twist = Twist{};
  if (!cfg_.alternatives || std::fabs(w) < 1e-6) return out;  // straight: slower is the same path
  constexpr int kAlts = 4;
  const double k[kAlts][2] = {{1.0, 0.5}, {1.0, 0.0}, {0.5, 1.0}, {0.25, 1.0}};
  bool ok[kAlts] = {};
  double cut[kAlts] = {};
  for (int i = 0; i < kAlts; ++i) {
    const Twist alt{want.vx * k[i][0], want.vy * k[i][0], want.wz * k[i][1]};
    double free = 0.0;
    ok[i] = translation(alt, reach, cut[i], free);
    if (ok[i] && cut[i] >= 1.0) return take(out, alt, 1.0);
  }
  // A turn on the spot where the arc was tight (radius within twice the body's): what the arc
  // was for.
  if (std::fabs(w) * 2.0 * fp_.circumscribed_m() >= v &&
      (cfg_.round_body || guard_.rotation_clear(std::copysign(std::min(turn, 2.0 * kPi), w)))) {
    return take(out, Twist{0.0, 0.0, w}, 1.0);
  }
  for (int i = 0; i < kAlts; ++i) {
    if (ok[i])
      return take(out, Twist{want.vx * k[i][0], want.vy * k[i][0], want.wz * k[i][1]}, cut[i]);
  }
  return out;
}

MotionVerdict& MotionCheck::take(MotionVerdict& out, const Twist& t, double scale) {
  out.clear = out.alternative = true;
  out.scale = scale;
  out.twist = Twist{t.vx * scale, t.vy * scale, t.wz * scale};
  return out;
}

bool MotionCheck::translation(const Twist& t, double reach, double& scale, double& free) const {
  free = guard_.free_travel(t, reach);
  scale = 1.0;
  if (free >= reach) return true;
  // Cut to the speed whose stop (a reaction's travel and the braking) fits the free travel: the
  // padded body's, so the pad is the margin here, counted once.
  const double fits = fields_.static_cap_mps(free + fields_.static_margin_m);
  if (fits < kTurnOnlyMps * 0.2) return false;
  scale = std::min(1.0, fits / std::hypot(t.vx, t.vy));
  return true;
}

}  // namespace carril::fw
