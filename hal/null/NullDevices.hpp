#pragma once
// Stand-ins for hardware a target lacks: they report "nothing there", never invent data.
#include "hal/Camera.hpp"
#include "hal/Imu.hpp"
#include "hal/RangeScanner.hpp"
#include "hal/WheelDrives.hpp"

namespace carril::hal {

class NullCamera final : public Camera {
 public:
  const CameraFrame* latest() override { return nullptr; }
};

class NullRangeScanner final : public RangeScanner {
 public:
  const LaserScan* latest() override { return nullptr; }
};

class NullImu final : public Imu {
 public:
  ImuSample read() override { return {}; }
};

// Drives that never enable: the firmware sees them Disabled and will not move.
class NullWheelDrives final : public WheelDrives {
 public:
  explicit NullWheelDrives(int count) : count_(count) {}
  // Nothing to bring up.
  DriveInitResult init() override { return DriveInitResult::success(); }
  int count() const override { return count_; }
  void enable() override {}
  void disable() override {}
  void quick_stop() override {}
  void reset_faults() override {}
  void set_velocity(const float*, int) override {}
  // No bus, so nothing to transfer.
  void sync() override {}
  void read(WheelFeedbackSet& out) const override;

 private:
  int count_;
};

}  // namespace carril::hal
