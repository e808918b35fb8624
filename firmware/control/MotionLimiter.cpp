#include "firmware/control/MotionLimiter.hpp"

#include "firmware/core/Param.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

Twist MotionLimiter::apply(const Twist& want, float* wheel_radps) {
  Twist t = want;
  if (!kin_.holonomic()) t.vy = 0.0;
  // Speed cap on the translational norm.
  const double v = std::hypot(t.vx, t.vy);
  if (v > lim_.max_speed_mps) {
    const double k = lim_.max_speed_mps / v;
    t.vx *= k;
    t.vy *= k;
  }
  t.wz = clampd(t.wz, -lim_.max_yaw_rate_radps, lim_.max_yaw_rate_radps);
  // Acceleration limits relative to the previous command.
  const double dvx = t.vx - last_.vx, dvy = t.vy - last_.vy;
  const double dv = std::hypot(dvx, dvy);
  const double dv_max = lim_.max_accel_mps2 * dt_;
  if (dv > dv_max) {
    const double k = dv_max / dv;
    t.vx = last_.vx + dvx * k;
    t.vy = last_.vy + dvy * k;
  }
  const double dw_max = lim_.max_yaw_accel_radps2 * dt_;
  t.wz = clampd(t.wz, last_.wz - dw_max, last_.wz + dw_max);
  // Wheel saturation: scale the whole twist so the fastest wheel is at its limit.
  kin_.inverse(t, wheel_radps);
  // std::max, not std::fmax: aarch64 g++ 12.2 crashes vectorising an fmax reduction at -O3.
  double peak = 0.0;
  for (int i = 0; i < kin_.wheel_count(); ++i)
    peak = std::max(peak, std::fabs(double(wheel_radps[i])));
  if (peak > lim_.max_wheel_speed_radps) {
    const double k = lim_.max_wheel_speed_radps / peak;
    t.vx *= k;
    t.vy *= k;
    t.wz *= k;
    kin_.inverse(t, wheel_radps);
  }
  last_ = t;
  return t;
}

}  // namespace carril::fw

namespace carril::fw {

std::span<const Param<MotionLimits>> MotionLimits::params() {
  using C = MotionLimits;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, max_speed_mps, "m/s", 0.05, 5.0, "body speed: the robot file's limits",
                   nullptr, false),
      CARRIL_PARAM(C, max_yaw_rate_radps, "rad/s", 0.05, 10.0,
                   "body yaw rate: the robot file's limits", nullptr, false),
      CARRIL_PARAM(C, max_accel_mps2, "m/s^2", 0.05, 20.0,
                   "body acceleration: the robot file's limits", nullptr, false),
      CARRIL_PARAM(C, max_yaw_accel_radps2, "rad/s^2", 0.01, 50.0,
                   "body yaw acceleration (the one motion limit the robot file does not carry)"),
      CARRIL_PARAM(C, max_wheel_speed_radps, "rad/s", 0.5, 500.0,
                   "wheel speed: the robot file's limits", nullptr, false),
  };
  return kParams;
}

Status MotionLimits::validate() const {
  return Checks("limits").params(*this, params()).result();
}

}  // namespace carril::fw
