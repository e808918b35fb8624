#pragma once
// A 3D lidar's sweep (e.g. a Velodyne HDL-32E: 32 beams x about 1800 azimuths at 10 Hz) and the
// sensor that delivers it. Fixed maximum size: a driver or the simulator fills it in place.
#include <array>
#include <cstdint>

#include "hal/Types.hpp"

namespace carril::hal {

constexpr int kMaxCloudPoints = 65536;  // 32 rings x 2048 azimuths

// One return, in the sensor frame: x forward, y left, z up, origin at the optical centre [m].
struct CloudPoint {
  float x = 0.0F;  // [m]
  float y = 0.0F;  // [m]
  float z = 0.0F;  // [m]
};

struct PointCloud {
  std::uint32_t seq = 0;    // increments with every sweep; 0 = none yet
  TimeNs stamp_ns = 0;      // end of the sweep [ns]
  std::uint32_t count = 0;  // valid entries in points (beams without a return are left out)
  std::array<CloudPoint, kMaxCloudPoints> points{};
};

class PointCloudSensor {
 public:
  virtual ~PointCloudSensor() = default;
  // Newest complete sweep, or nullptr if none has arrived. It stays valid and unchanged for as
  // long as later calls return it (the same seq): a consumer may read it over several ticks.
  virtual const PointCloud* latest() = 0;
};

}  // namespace carril::hal
