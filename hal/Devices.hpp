#pragma once
// The set of devices one firmware instance talks to. Filled in by each target's wiring file.
#include "hal/Camera.hpp"
#include "hal/Clock.hpp"
#include "hal/Imu.hpp"
#include "hal/PointCloud.hpp"
#include "hal/RangeScanner.hpp"
#include "hal/WheelDrives.hpp"

namespace carril::hal {

struct Devices {
  Clock& clock;
  WheelDrives& drives;
  Camera& camera;
  RangeScanner& scanner;
  Imu& imu;
  PointCloudSensor* cloud = nullptr;  // a 3D lidar, where one is fitted
};

}  // namespace carril::hal
