#include "firmware/estimation/OdometryMotionModel.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

OdometryDelta OdometryMotionModel::delta(const Pose2& from, const Pose2& to) const {
  OdometryDelta d;
  const double dx = to.x - from.x, dy = to.y - from.y;
  d.trans = std::sqrt(dx * dx + dy * dy);
  // Below 1 cm the direction of travel is noise (a turn in place): all of the turn is rot2.
  d.rot1 = d.trans < 0.01 ? 0.0 : wrap_angle(std::atan2(dy, dx) - from.yaw);
  d.rot2 = wrap_angle(to.yaw - from.yaw - d.rot1);
  // Backwards is not a half turn: the noise sees rot1 and rot2 folded towards 0 or pi.
  const auto fold = [](double a) { return std::min(std::abs(a), std::abs(kPi - std::abs(a))); };
  const double r1 = fold(d.rot1), r2 = fold(d.rot2), t = d.trans;
  const OdometryNoise& n = noise_;
  d.sd_rot1 = std::sqrt(n.alpha1 * r1 * r1 + n.alpha2 * t * t);
  d.sd_trans = std::sqrt(n.alpha3 * t * t + n.alpha4 * (r1 * r1 + r2 * r2));
  d.sd_rot2 = std::sqrt(n.alpha1 * r2 * r2 + n.alpha2 * t * t);
  return d;
}

}  // namespace carril::fw
