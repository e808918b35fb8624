#pragma once
// The odometry motion model (Probabilistic Robotics, table 5.6, sample_motion_model_odometry):
// the motion between two odometry poses is a rotation rot1 towards the direction of travel, a
// translation trans and a rotation rot2; each is disturbed by zero-mean Gaussian noise of
// variance
//   rot1:  alpha1 rot1^2 + alpha2 trans^2
//   trans: alpha3 trans^2 + alpha4 (rot1^2 + rot2^2)
//   rot2:  alpha1 rot2^2 + alpha2 trans^2.
// Two changes, as AMCL's differential model makes them: a translation under 1 cm has no
// direction (rot1 = 0, the turn goes into rot2), and the rotation noise uses rot1 folded to the
// nearer of forward and backward (driving backwards is not a half turn). A sideways motion (a
// holonomic base) is represented exactly (rot1 = +-90 deg, rot2 = -+90 deg), but it is charged
// the rotation noise of a 90 deg turn: conservative, fine for the differential and skid-steer
// robots this targets.
#include "firmware/core/Geometry.hpp"
#include "firmware/estimation/MclMath.hpp"
#include "firmware/estimation/MclRandom.hpp"

namespace carril::fw {

struct OdometryNoise {
  double alpha1 = 0.2;  // rotation noise from rotation [rad^2/rad^2]
  double alpha2 = 0.2;  // rotation noise from translation [rad^2/m^2]
  double alpha3 = 0.2;  // translation noise from translation [m^2/m^2]
  double alpha4 = 0.2;  // translation noise from rotation [m^2/rad^2]
};

// One odometry motion decomposed, with the standard deviation of each part's noise.
struct OdometryDelta {
  double rot1 = 0.0, trans = 0.0, rot2 = 0.0;           // [rad, m, rad]
  double sd_rot1 = 0.0, sd_trans = 0.0, sd_rot2 = 0.0;  // [rad, m, rad]
};

class OdometryMotionModel {
 public:
  explicit OdometryMotionModel(const OdometryNoise& noise = {}) : noise_(noise) {}

  // The motion from odometry pose `from` to `to` and its noise.
  OdometryDelta delta(const Pose2& from, const Pose2& to) const;

  // A successor of pose p under d, drawn from the model (yaw wrapped to [-pi, pi]).
  static Pose2 sample(const Pose2& p, const OdometryDelta& d, MclRng& rng) {
    const double r1 = d.rot1 - d.sd_rot1 * rng.gaussian();
    const double t = d.trans - d.sd_trans * rng.gaussian();
    const double r2 = d.rot2 - d.sd_rot2 * rng.gaussian();
    const double heading = p.yaw + r1;
    double s = 0.0, c = 0.0;
    fast_sincos(heading, s, c);
    return {p.x + t * c, p.y + t * s, wrap_angle(heading + r2)};
  }

  const OdometryNoise& noise() const { return noise_; }

 private:
  OdometryNoise noise_;
};

}  // namespace carril::fw
