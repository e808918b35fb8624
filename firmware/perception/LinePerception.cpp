#include "firmware/perception/LinePerception.hpp"

namespace carril::fw {

Status LinePerceptionConfig::validate() const {
  return Checks("camera")
      .range("rate_hz", rate_hz, 1.0, 1000.0, "Hz")
      .nested(camera.validate())
      .nested(detector.validate())
      .nested(health.validate())
      .result();
}

LinePerception::LinePerception(const LinePerceptionConfig& cfg, const Topic<SensorFrame>& frame,
                               const Topic<OdometryMsg>& odom, Topic<LineObservation>& out,
                               FaultSink& faults)
    : cfg_(cfg),
      cam_(cfg.camera),
      detector_(cam_, cfg.detector),
      health_(cfg.health),
      frame_(frame),
      odom_(odom),
      out_(out),
      faults_(faults) {}

LinePerceptionTelemetry LinePerception::telemetry() const {
  return {processed_, health_.last_spread()};
}

void LinePerception::run() {
  const SensorFrame& f = frame_.get();
  const hal::CameraFrame* cam = frames_.take(f.camera);
  if (cam == nullptr) return;
  LineObservation& obs = out_.edit();
  if (!detector_.detect(*cam, obs.detection)) {
    faults_.raise(Fault::CameraBadFrame);
    return;
  }
  const Pose2& pose = odom_.get().pose;
  switch (health_.add(*cam, pose)) {
    case FrameVerdict::Blank:
      faults_.raise(Fault::CameraBlank);
      return;
    case FrameVerdict::Frozen:
      faults_.raise(Fault::CameraFrozen);
      return;
    case FrameVerdict::Ok:
      break;
  }
  ++processed_;
  obs.pose = pose;
  const LineDetection& det = obs.detection;
  // The end mark's position is only trusted when all of it is in view.
  obs.end_visible = det.end_detected && !det.end_blob.touches_edge;
  obs.end_glimpsed = det.end_detected && det.end_blob.touches_edge;
  if (obs.end_visible) {
    // A disc seen in perspective has its image centroid pulled toward the near side; the middle
    // of its nearest and farthest points (bottom and top of the blob) on the floor is its centre.
    const Blob& b = det.end_blob;
    const double uc = 0.5 * (b.u_min + b.u_max);
    Vec2 near, far;
    const bool ok = cam_.pixel_to_floor(Vec2(uc, b.v_max + 0.5), near) &&
                    cam_.pixel_to_floor(Vec2(uc, b.v_min - 0.5), far);
    obs.end_floor = ok ? Vec2(0.5 * (near + far)) : det.end_floor;
  }
  out_.publish(f.now_ns);
}

}  // namespace carril::fw
