// The vacuum coverage mission: the reactive baseline. See VacuumCoverage.hpp.
#include "firmware/mission/VacuumCoverage.hpp"

namespace carril::fw {

void VacuumCoverage::restart() {
  rng_ = cfg_.seed != 0 ? cfg_.seed : 1u;
}

MissionOutput VacuumCoverage::begin(const Pose2&) {
  go(State::Spiral, "spiral");
  return {};
}

// xorshift32: a fixed sequence per seed, no state beyond one word.
double VacuumCoverage::uniform() {
  rng_ ^= rng_ << 13;
  rng_ ^= rng_ >> 17;
  rng_ ^= rng_ << 5;
  return double(rng_) / 4294967296.0;
}

bool VacuumCoverage::bumped(const MissionContext& ctx, const Pose2& pose) const {
  return ctx.obstacle_ahead() || lethal_near(pose, cfg_.vacuum.bump_m, true, true);
}

MissionOutput VacuumCoverage::step(const MissionContext& ctx, const Pose2& pose) {
  const VacuumConfig& v = cfg_.vacuum;
  const double t = now_s_ - state_t0_s_;
  MissionOutput out;
  switch (state_) {
    case State::Spiral:
    case State::Forward:
      if (bumped(ctx, pose)) {
        ++bumps_;
        go(State::BackUp, "back_up");
        return out;
      }
      if (state_ == State::Spiral) {
        if (t >= v.spiral_max_s) {
          go(State::Forward, "forward");
          return out;
        }
        const double r = v.spiral_start_radius_m + v.spiral_growth_mps * t;
        out.motion.twist.vx = v.spiral_speed_mps;
        out.motion.twist.wz = v.spiral_speed_mps / r;
        return out;
      }
      if (t >= v.forward_s) {
        go(State::Spiral, "spiral");
        return out;
      }
      out.motion.twist.vx = v.forward_speed_mps;
      return out;
    case State::BackUp:
      if (t >= v.backup_s || lethal_near(pose, v.bump_m, false, true)) {
        turn_dir_ = uniform() < 0.5 ? 1.0 : -1.0;
        turn_s_ = v.turn_min_s + (v.turn_max_s - v.turn_min_s) * uniform();
        ++(turn_dir_ > 0.0 ? turns_left_ : turns_right_);
        go(State::Turn, turn_dir_ > 0.0 ? "turn_left" : "turn_right");
        return out;
      }
      out.motion.twist.vx = -v.backup_speed_mps;
      return out;
    case State::Turn:
      if (t >= turn_s_) {
        go(State::Forward, "forward");
        return out;
      }
      out.motion.twist.wz = turn_dir_ * v.turn_rate_radps;
      return out;
    default:
      return out;
  }
}

}  // namespace carril::fw
