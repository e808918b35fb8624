#pragma once
// What one tick consumes and produces.
#include <array>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "hal/PointCloud.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// Sensor snapshot assembled from the HAL before each tick. Pointers reference HAL-owned buffers,
// valid for this tick only; nullptr when the device has delivered nothing.
struct SensorFrame {
  hal::TimeNs now_ns = 0;  // loop time [ns]
  const hal::CameraFrame* camera = nullptr;
  const hal::LaserScan* scan = nullptr;
  const hal::PointCloud* cloud = nullptr;  // 3D lidar sweep; nullptr without one
  hal::ImuSample imu{};
  hal::WheelFeedbackSet wheels{};
};

enum class DriveRequest : std::uint8_t {
  Disable,    // drives off
  Run,        // enable and follow wheel_radps
  QuickStop,  // brake to zero and hold (safe stop)
};

// Every one of the first `wheels` drives reports Operation enabled.
inline bool drives_enabled(const hal::WheelFeedbackSet& fb, int wheels) {
  if (fb.count < wheels) return false;
  for (int i = 0; i < wheels; ++i) {
    if (fb.wheel[i].state != hal::DriveState::Enabled) return false;
  }
  return true;
}

struct ActuatorCommand {
  DriveRequest drive = DriveRequest::QuickStop;
  std::uint8_t wheel_count = 0;
  std::array<float, hal::kMaxWheels> wheel_radps{};  // setpoints [rad/s]
  Twist twist;                                       // body twist these come from [m/s, rad/s]
};

}  // namespace carril::fw
