#pragma once
// Message `frame`: what one tick consumes, assembled from the HAL before the tick.
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

}  // namespace carril::fw
