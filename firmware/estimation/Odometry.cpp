#include "firmware/estimation/Odometry.hpp"

#include <cmath>

namespace carril::fw {

bool Odometry::gyro_turn(const hal::ImuSample& imu, double& dyaw) {
  if (!gyro_heading_) return false;
  const double rate = double(imu.yaw_rate_radps);
  if (!imu.valid || !std::isfinite(rate)) {
    gyro_primed_ = false;
    return false;
  }
  if (gyro_primed_ && imu.stamp_ns == last_imu_ns_) {
    dyaw = 0.0;  // no new sample this step: its interval is integrated with the next one
    return true;
  }
  const bool usable =
      gyro_primed_ && imu.stamp_ns > last_imu_ns_ && imu.stamp_ns - last_imu_ns_ <= kMaxGyroGapNs;
  if (usable) dyaw = 0.5 * (rate + last_rate_) * double(imu.stamp_ns - last_imu_ns_) * 1e-9;
  gyro_primed_ = true;
  last_imu_ns_ = imu.stamp_ns;
  last_rate_ = rate;
  return usable;
}

void Odometry::update(const hal::WheelFeedbackSet& fb, const hal::ImuSample& imu) {
  const int n = kin_.wheel_count();
  if (fb.count < n) return;
  float vel[hal::kMaxWheels] = {};
  double delta[hal::kMaxWheels] = {};
  for (int i = 0; i < n; ++i) {
    vel[i] = fb.wheel[i].velocity_radps;
    delta[i] = primed_ ? fb.wheel[i].position_rad - last_pos_[i] : 0.0;
    last_pos_[i] = fb.wheel[i].position_rad;
  }
  const bool first = !primed_;
  primed_ = true;
  twist_ = kin_.forward(vel);
  const Twist d = kin_.forward_delta(delta);
  double dyaw = 0.0;
  const bool gyro = gyro_turn(imu, dyaw) && !first;
  if (!gyro) dyaw = d.wz;
  ++(gyro ? gyro_steps_ : wheel_steps_);
  // Midpoint integration: the step's translation is taken at the average heading.
  const double mid = pose_.yaw + 0.5 * dyaw;
  const double c = std::cos(mid), s = std::sin(mid);
  pose_.x += c * d.vx - s * d.vy;
  pose_.y += s * d.vx + c * d.vy;
  pose_.yaw = wrap_angle(pose_.yaw + dyaw);
}

}  // namespace carril::fw
