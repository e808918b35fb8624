#include "firmware/app/Localisation.hpp"

#include <algorithm>
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
      .range("initial_sigma_xy_m", initial_sigma_xy_m, 0.0, 100.0, "m")
      .range("initial_sigma_yaw_rad", initial_sigma_yaw_rad, 0.0, 2.0 * kPi, "rad")
      .range("particles_per_tick", double(particles_per_tick), 10.0, 1e6, "particles")
      .range("localised_sigma_xy_m", localised_sigma_xy_m, 0.01, 10.0, "m")
      .range("localised_sigma_yaw_rad", localised_sigma_yaw_rad, 0.01, kPi, "rad")
      .nested(mcl.validate())
      .result();
}

Localisation::Localisation(const LocalisationConfig& cfg, const OccupancyGrid* map,
                           const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
                           Topic<OdometryMsg>& pose)
    : cfg_(cfg), map_(map), frame_(frame), odom_(odom), out_(pose) {
  if (!cfg_.enabled || map_ == nullptr) return;
  // The odometry frame starts where the robot does: at the initial pose in the map frame.
  map_from_odom_ = cfg_.initial_pose;
  mcl_ = std::make_unique<MonteCarloLocalizer>(cfg_.mcl, *map_);
  if (cfg_.global) {
    mcl_->set_global();
  } else {
    mcl_->set_pose(cfg_.initial_pose, cfg_.initial_sigma_xy_m, cfg_.initial_sigma_yaw_rad);
  }
}

void Localisation::take_estimate() {
  map_from_odom_ = mcl_->map_from_odom();
  const Mat3& c = mcl_->covariance();
  // Largest standard deviation of the 2 x 2 position block (its larger eigenvalue).
  const double a = c(0, 0), b = c(0, 1), d = c(1, 1);
  const double l1 = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  tel_.sigma_xy_m = std::sqrt(std::max(0.0, l1));
  tel_.sigma_yaw_rad = std::sqrt(std::max(0.0, c(2, 2)));
  const double k = localised_ ? 2.0 : 1.0;  // hysteresis: lost only beyond twice the bounds
  const bool ok = tel_.sigma_xy_m <= k * cfg_.localised_sigma_xy_m &&
                  tel_.sigma_yaw_rad <= k * cfg_.localised_sigma_yaw_rad;
  if (localised_ && !ok) ++tel_.lost;
  localised_ = ok;
}

void Localisation::run() {
  const OdometryMsg& o = odom_.get();
  if (mcl_ != nullptr) {
    const SensorFrame& f = frame_.get();
    if (!mcl_->busy() && f.scan != nullptr && f.scan->seq != 0 && f.scan->seq != last_scan_seq_) {
      last_scan_seq_ = f.scan->seq;
      // Held still while lost, the robot would never move enough to update: weigh every scan.
      if (!localised_) mcl_->force_next_update();
      (void)mcl_->begin_update(*f.scan, o.pose, cfg_.lidar_mount);
    } else if (mcl_->busy()) {
      (void)mcl_->step(cfg_.particles_per_tick);
    }
    if (mcl_->telemetry().updates != seen_updates_) {
      seen_updates_ = mcl_->telemetry().updates;
      take_estimate();
    }
    tel_.updates = seen_updates_;
    tel_.particles = mcl_->particle_count();
  }
  OdometryMsg& m = out_.edit();
  // Without a map the odometry frame is the map frame: passed on unchanged, bit for bit.
  m.pose = mcl_ != nullptr ? compose(map_from_odom_, o.pose) : o.pose;
  m.twist = o.twist;
  m.localised = mcl_ == nullptr || localised_;
  out_.publish(frame_.get().now_ns);
  tel_.pose = m.pose;
  tel_.localised = m.localised;
}

const LocalisationTelemetry& Localisation::telemetry() const {
  if (mcl_ != nullptr) tel_.mcl = mcl_->telemetry();
  return tel_;
}

}  // namespace carril::fw
