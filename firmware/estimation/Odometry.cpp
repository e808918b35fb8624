#include "firmware/estimation/Odometry.hpp"

#include <cmath>

namespace carril::fw {

void Odometry::update(const hal::WheelFeedbackSet& fb) {
  const int n = kin_.wheel_count();
  if (fb.count < n) return;
  float vel[hal::kMaxWheels] = {};
  double delta[hal::kMaxWheels] = {};
  for (int i = 0; i < n; ++i) {
    vel[i] = fb.wheel[i].velocity_radps;
    delta[i] = primed_ ? fb.wheel[i].position_rad - last_pos_[i] : 0.0;
    last_pos_[i] = fb.wheel[i].position_rad;
  }
  primed_ = true;
  twist_ = kin_.forward(vel);
  const Twist d = kin_.forward_delta(delta);
  // Midpoint integration: the step's translation is taken at the average heading.
  const double mid = pose_.yaw + 0.5 * d.wz;
  const double c = std::cos(mid), s = std::sin(mid);
  pose_.x += c * d.vx - s * d.vy;
  pose_.y += s * d.vx + c * d.vy;
  pose_.yaw = wrap_angle(pose_.yaw + d.wz);
}

}  // namespace carril::fw
