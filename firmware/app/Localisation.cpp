#include "firmware/app/Localisation.hpp"

#include <cmath>

namespace carril::fw {

Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.yaw + b.yaw)};
}

Pose2 inverse(const Pose2& p) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), wrap_angle(-p.yaw)};
}

Status LocalisationConfig::validate() const {
  Checks c("localisation");
  if (!enabled) return c.result();
  return c.range("initial_pose.x", initial_pose.x, -1e4, 1e4, "m")
      .range("initial_pose.y", initial_pose.y, -1e4, 1e4, "m")
      .range("initial_pose.yaw", initial_pose.yaw, -2.0 * kPi, 2.0 * kPi, "rad")
      .result();
}

Localisation::Localisation(const LocalisationConfig& cfg, const OccupancyGrid* map,
                           const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
                           Topic<OdometryMsg>& pose)
    : cfg_(cfg), map_(map), frame_(frame), odom_(odom), out_(pose) {
  // The odometry frame starts where the robot does: at the initial pose in the map frame.
  if (cfg_.enabled) map_from_odom_ = cfg_.initial_pose;
}

void Localisation::run() {
  const OdometryMsg& o = odom_.get();
  OdometryMsg& m = out_.edit();
  // Without a map the odometry frame is the map frame: passed on unchanged, bit for bit.
  m.pose = cfg_.enabled ? compose(map_from_odom_, o.pose) : o.pose;
  m.twist = o.twist;
  out_.publish(frame_.get().now_ns);
  tel_.pose = m.pose;
}

}  // namespace carril::fw
