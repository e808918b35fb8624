#include "firmware/health/SensorWatch.hpp"

#include "firmware/core/Param.hpp"

namespace carril::fw {

std::span<const Param<SensorWatchConfig>> SensorWatchConfig::params() {
  using C = SensorWatchConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, camera_timeout_s, "s", 0.01, 10.0, "no frame this long: `camera_timeout`",
                   "3 frames, at least 0.2 s"),
      CARRIL_PARAM(C, scanner_timeout_s, "s", 0.01, 10.0, "no scan this long: `scanner_timeout`",
                   "5 scans, at least 0.5 s"),
      CARRIL_PARAM(C, imu_timeout_s, "s", 0.01, 10.0,
                   "a fitted IMU with no valid sample this long (or none by the end of start-up): "
                   "`imu_timeout`"),
  };
  return kParams;
}

Status SensorWatchConfig::validate() const {
  return Checks("watch").params(*this, params()).nested(imu.validate()).result();
}

SensorWatch::SensorWatch(const SensorWatchConfig& cfg, bool lidar_present,
                         const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
                         FaultSink& faults)
    : cfg_(cfg),
      lidar_present_(lidar_present),
      frame_(frame),
      odom_(odom),
      faults_(faults),
      imu_health_(cfg.imu) {}

void SensorWatch::run() {
  const SensorFrame& f = frame_.get();
  const double now_s = double(f.now_ns) * 1e-9;
  for (int i = 0; i < f.wheels.count; ++i) {
    if (f.wheels.wheel[i].state == hal::DriveState::Fault) {
      faults_.raise(Fault::DriveFault, static_cast<std::uint16_t>(f.wheels.wheel[i].fault));
    }
  }
  // A device is silent when nothing new came for its timeout; before its first sample the
  // mission's own start-up timeout applies.
  if (frames_.take(f.camera) != nullptr) {
    last_frame_ns_ = f.now_ns;
    ++tel_.camera_frames;
  }
  if (scans_.take(f.scan) != nullptr) {
    last_scan_ns_ = f.now_ns;
    ++tel_.scans;
  }
  if (frames_.ever() && now_s - double(last_frame_ns_) * 1e-9 > cfg_.camera_timeout_s) {
    faults_.raise(Fault::CameraTimeout);
  }
  if (lidar_present_ && scans_.ever() &&
      now_s - double(last_scan_ns_) * 1e-9 > cfg_.scanner_timeout_s) {
    faults_.raise(Fault::ScannerTimeout);
  }
  if (cfg_.imu_present) {
    // Silence: no valid sample at all (a sample that keeps its stamp is the frozen rule's).
    if (f.imu.valid) {
      imu_seen_ = true;
      last_imu_ns_ = f.now_ns;
      ++tel_.imu_samples;
    } else if (imu_seen_ && now_s - double(last_imu_ns_) * 1e-9 > cfg_.imu_timeout_s) {
      faults_.raise(Fault::ImuTimeout);
    }
    switch (imu_health_.add(f.imu, now_s, odom_.get().twist.wz)) {
      case ImuVerdict::OutOfRange:
        faults_.raise(Fault::ImuOutOfRange);
        break;
      case ImuVerdict::Frozen:
        faults_.raise(Fault::ImuFrozen);
        break;
      case ImuVerdict::Ok:
        break;
    }
  }
}

}  // namespace carril::fw
