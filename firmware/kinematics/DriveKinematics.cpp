#include "firmware/kinematics/DriveKinematics.hpp"

namespace carril::fw {

DriveKinematics::DriveKinematics(const DriveGeometry& g) : g_(g) {
  const double r = g.wheel_radius_m;
  inv_.setZero();
  fwd_.setZero();
  if (g.type == DriveType::Mecanum) {
    n_ = 4;
    const double l = 0.5 * (g.wheelbase_m + g.track_m);  // lx + ly
    // omega_i = (vx + s_y*vy + s_w*l*wz) / r
    inv_ << 1, -1, -l,  //
        1, 1, l,        //
        1, 1, -l,       //
        1, -1, l;
    inv_ /= r;
    fwd_ << 1, 1, 1, 1,  //
        -1, 1, 1, -1,    //
        -1 / l, 1 / l, -1 / l, 1 / l;
    fwd_ *= r / 4.0;
  } else {
    n_ = 2;
    const double h = 0.5 * g.track_m;
    inv_(0, 0) = 1 / r;
    inv_(0, 2) = -h / r;
    inv_(1, 0) = 1 / r;
    inv_(1, 2) = h / r;
    fwd_(0, 0) = r / 2;
    fwd_(0, 1) = r / 2;
    fwd_(2, 0) = -r / g.track_m;
    fwd_(2, 1) = r / g.track_m;
  }
}

void DriveKinematics::inverse(const Twist& t, float* wheel_radps) const {
  const Eigen::Vector3d v(t.vx, t.vy, t.wz);
  const Eigen::Vector4d w = inv_ * v;
  for (int i = 0; i < n_; ++i) wheel_radps[i] = static_cast<float>(w[i]);
}

Twist DriveKinematics::forward(const float* wheel_radps) const {
  Eigen::Vector4d w = Eigen::Vector4d::Zero();
  for (int i = 0; i < n_; ++i) w[i] = double(wheel_radps[i]);
  const Eigen::Vector3d v = fwd_ * w;
  return {v[0], v[1], v[2]};
}

Twist DriveKinematics::forward_delta(const double* wheel_delta_rad) const {
  Eigen::Vector4d w = Eigen::Vector4d::Zero();
  for (int i = 0; i < n_; ++i) w[i] = wheel_delta_rad[i];
  const Eigen::Vector3d v = fwd_ * w;
  return {v[0], v[1], v[2]};
}

}  // namespace carril::fw

namespace carril::fw {

Status DriveGeometry::validate() const {
  return Checks("drive")
      .range("wheel_radius_m", wheel_radius_m, kWheelRadiusMinM, kWheelRadiusMaxM, "m")
      .range("wheelbase_m", wheelbase_m, kWheelSpanMinM, kWheelSpanMaxM, "m")
      .range("track_m", track_m, kWheelSpanMinM, kWheelSpanMaxM, "m")
      .fail_if(type == DriveType::Mecanum && !(wheelbase_m > 0.0), "wheelbase_m",
               "a mecanum robot needs a wheelbase > 0 m")
      .result();
}

}  // namespace carril::fw
