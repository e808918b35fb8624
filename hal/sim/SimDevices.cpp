#include "hal/sim/SimDevices.hpp"

#include <cassert>
#include <chrono>
#include <cstring>
#include <limits>

namespace carril::hal {

TimeNs SimClock::cpu_now_ns() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

SimCamera::SimCamera()
    : frame_(std::make_unique<CameraFrame>()), frozen_(std::make_unique<CameraFrame>()) {}

const CameraFrame* SimCamera::latest() {
  if (seq_ == 0 || fault_ == SimSensorFault::Silent) return nullptr;
  return frame_.get();
}

void SimCamera::publish(TimeNs stamp_ns) {
  // Silent and None leave the buffer as rendered; the other faults write into it or resize it.
  as_rendered_ = fault_ == SimSensorFault::None || fault_ == SimSensorFault::Silent;
  if (fault_ == SimSensorFault::Silent) return;
  frame_->stamp_ns = stamp_ns;
  frame_->seq = ++seq_;
  const std::size_t bytes = std::size_t(frame_->width) * frame_->height * 3;
  if (fault_ == SimSensorFault::WrongSize) {
    // Half the configured size, same buffer: what a misconfigured capture driver delivers.
    frame_->width = static_cast<std::uint16_t>(frame_->width / 2);
    frame_->height = static_cast<std::uint16_t>(frame_->height / 2);
  } else if (fault_ == SimSensorFault::Blank) {
    std::memset(frame_->bgr.data(), 0, bytes);  // black: a lens cap
  } else if (fault_ == SimSensorFault::Frozen) {
    // The first frozen frame is the last good image; every later one repeats it.
    if (!frozen_taken_) {
      std::memcpy(frozen_->bgr.data(), frame_->bgr.data(), bytes);
      frozen_taken_ = true;
    }
    std::memcpy(frame_->bgr.data(), frozen_->bgr.data(), bytes);
  }
  if (fault_ != SimSensorFault::Frozen) frozen_taken_ = false;
}

SimRangeScanner::SimRangeScanner() : scan_(std::make_unique<LaserScan>()) {}

const LaserScan* SimRangeScanner::latest() {
  if (seq_ == 0 || fault_ == SimSensorFault::Silent) return nullptr;
  return scan_.get();
}

void SimRangeScanner::publish(TimeNs stamp_ns) {
  if (fault_ == SimSensorFault::Silent) return;
  scan_->stamp_ns = stamp_ns;
  scan_->seq = ++seq_;
  float garbage = 0.0F;
  switch (fault_) {
    case SimSensorFault::NanRanges:
      garbage = std::numeric_limits<float>::quiet_NaN();
      break;
    case SimSensorFault::ZeroRanges:
      garbage = 0.0F;
      break;
    case SimSensorFault::OutOfLimitRanges:
      garbage = 2.0F * scan_->range_max_m + 1.0F;
      break;
    default:
      return;
  }
  for (int i = 0; i < scan_->count && i < kMaxScanBeams; ++i)
    scan_->ranges_m[std::size_t(i)] = garbage;
}

void SimImu::publish(const ImuSample& s) {
  switch (fault_) {
    case SimSensorFault::Frozen:
      if (!sample_.valid) sample_ = s;  // nothing to repeat yet
      return;
    case SimSensorFault::OutOfRange:
      sample_ = s;
      sample_.roll_rad = std::numeric_limits<float>::quiet_NaN();
      sample_.yaw_rate_radps = 1000.0F;
      return;
    default:
      sample_ = s;
      return;
  }
}

SimWheelDrives::SimWheelDrives(int count) : count_(count) {
  assert(count > 0 && count <= kMaxWheels);
  fb_.count = static_cast<std::uint8_t>(count);
}

DriveInitResult SimWheelDrives::init() {
  return init_result_;
}

void SimWheelDrives::fail_init(int wheel, const char* what) {
  init_result_ = DriveInitResult::failure(wheel, "%s", what);
}

void SimWheelDrives::enable() {
  enable_requested_.fill(true);
}

void SimWheelDrives::disable() {
  enable_requested_.fill(false);
  for (int i = 0; i < count_; ++i) {
    if (fb_.wheel[i].state != DriveState::Fault) fb_.wheel[i].state = DriveState::Disabled;
  }
}

void SimWheelDrives::quick_stop() {
  enable_requested_.fill(false);
  ++quick_stops_;
  for (int i = 0; i < count_; ++i) {
    if (fb_.wheel[i].state != DriveState::Fault) fb_.wheel[i].state = DriveState::QuickStop;
  }
}

void SimWheelDrives::reset_faults() {
  for (int i = 0; i < count_; ++i) {
    if (fb_.wheel[i].state == DriveState::Fault) {
      fb_.wheel[i].state = DriveState::Disabled;
      fb_.wheel[i].fault = DriveFault::None;
    }
  }
}

void SimWheelDrives::set_velocity(const float* radps, int n) {
  assert(n == count_);
  for (int i = 0; i < n && i < kMaxWheels; ++i) setpoint_[i] = radps[i];
}

void SimWheelDrives::read(WheelFeedbackSet& out) const {
  out = fb_;
}

void SimWheelDrives::sync() {
  ++syncs_;
  for (int i = 0; i < count_; ++i) {
    WheelFeedback& w = fb_.wheel[i];
    if (enable_requested_[std::size_t(i)]) {
      if (w.state == DriveState::Disabled || w.state == DriveState::QuickStop) {
        w.state = DriveState::Enabling;
      } else if (w.state == DriveState::Enabling) {
        w.state = DriveState::Enabled;
      }
    }
    latched_[std::size_t(i)] = (w.state == DriveState::Enabled) ? setpoint_[i] : 0.0F;
  }
}

void SimWheelDrives::take_setpoints(float* target_radps) const {
  for (int i = 0; i < count_; ++i) target_radps[i] = latched_[std::size_t(i)];
}

void SimWheelDrives::set_feedback(int wheel, TimeNs stamp_ns, float velocity_radps,
                                  double position_rad) {
  WheelFeedback& w = fb_.wheel[wheel];
  w.stamp_ns = stamp_ns;
  w.velocity_radps = velocity_radps;
  w.position_rad = position_rad;
}

void SimWheelDrives::inject_fault(int wheel, DriveFault code) {
  fb_.wheel[wheel].state = DriveState::Fault;
  fb_.wheel[wheel].fault = code;
  enable_requested_[std::size_t(wheel)] = false;
  setpoint_[std::size_t(wheel)] = 0.0F;
  latched_[std::size_t(wheel)] = 0.0F;  // a faulted drive stops following at once
}

}  // namespace carril::hal
