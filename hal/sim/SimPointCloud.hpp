#pragma once
// In-process 3D lidar backend: the simulator renders a sweep into back_buffer() and publishes
// it; the firmware reads it through hal::PointCloudSensor. Faults: Silent (no sweep ever
// delivered: latest() is nullptr) and Frozen (a stuck sensor: the last sweep, same seq, forever).
#include <memory>

#include "hal/PointCloud.hpp"
#include "hal/sim/SimDevices.hpp"

namespace carril::hal {

class SimPointCloud final : public PointCloudSensor {
 public:
  SimPointCloud() : front_(std::make_unique<PointCloud>()), back_(std::make_unique<PointCloud>()) {}
  // Newest published sweep; nullptr before the first one or while Silent.
  const PointCloud* latest() override {
    if (fault_ == SimSensorFault::Silent || front_->seq == 0) return nullptr;
    return front_.get();
  }
  // Simulator side: render into this, then publish().
  PointCloud& back_buffer() { return *back_; }
  // Makes the back buffer the newest sweep (a Frozen sensor keeps its old one).
  void publish() {
    if (fault_ == SimSensorFault::Frozen && front_->seq != 0) return;
    front_.swap(back_);
  }
  // None, Silent or Frozen.
  void inject_fault(SimSensorFault f) { fault_ = f; }

 private:
  std::unique_ptr<PointCloud> front_;  // what latest() hands out (786 kB each, sized once)
  std::unique_ptr<PointCloud> back_;   // what the simulator renders into
  SimSensorFault fault_ = SimSensorFault::None;
};

}  // namespace carril::hal
