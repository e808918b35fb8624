#include "firmware/perception/ObstacleSensing.hpp"

namespace carril::fw {

Status ObstacleSensingConfig::validate() const {
  return Checks("lidar")
      .range("rate_hz", rate_hz, 1.0, 1000.0, "Hz")
      .range("x_m", x_m, -5.0, 5.0, "m")
      .range("y_m", y_m, -5.0, 5.0, "m")
      .range("yaw_rad", yaw_rad, -7.0, 7.0, "rad")
      .range("reliable_range_m", reliable_range_m, 0.05, 100.0, "m")
      .nested(health.validate())
      .nested(moving.validate())
      .result();
}

ObstacleSensing::ObstacleSensing(const ObstacleSensingConfig& cfg, const Topic<SensorFrame>& frame,
                                 const Topic<OdometryMsg>& odom, Topic<ObstacleField>& out,
                                 FaultSink& faults)
    : health_(cfg.health),
      moving_(cfg.moving, cfg.rate_hz),
      frame_(frame),
      odom_(odom),
      out_(out),
      faults_(faults) {}

ObstacleSensingTelemetry ObstacleSensing::telemetry() const {
  return {out_.get().invalid_beams(), moving_returns_, health_.valid_fraction()};
}

void ObstacleSensing::run() {
  const SensorFrame& f = frame_.get();
  const hal::LaserScan* scan = scans_.take(f.scan);
  if (scan == nullptr) return;
  if (!health_.add(*scan)) faults_.raise(Fault::ScannerBlind);
  ObstacleField& field = out_.edit();
  field.update(*scan, odom_.get().pose);
  moving_.classify(*scan, odom_.get().pose, field);
  moving_returns_ += field.moving_count();
  out_.publish(f.now_ns);
}

}  // namespace carril::fw
