#pragma once
#include "hal/Types.hpp"

namespace carril::hal {

// Per-wheel velocity drives. Shaped after CiA 402 profile velocity mode: commands are requests
// that take effect through the drive's state machine (enable sequence, quick stop, fault reset);
// feedback reports what each drive actually did. Wheel order is fixed by the robot's kinematics
// (front-left, front-right, rear-left, rear-right; differential: left, right).
class WheelDrives {
 public:
  virtual ~WheelDrives() = default;
  // Number of wheels driven.
  virtual int count() const = 0;
  // Request Operation enabled on every drive (shutdown -> switch on -> enable operation).
  virtual void enable() = 0;
  // Request Disabled (power off the bridges).
  virtual void disable() = 0;
  // Brake every drive to zero on its quick-stop ramp; setpoints ignored until enable().
  virtual void quick_stop() = 0;
  // Clear a latched fault (fault reset); the drive returns to Disabled.
  virtual void reset_faults() = 0;
  // Velocity setpoints, one per wheel, applied at the next bus sync [rad/s].
  virtual void set_velocity(const float* radps, int n) = 0;
  // Latest feedback from every drive.
  virtual void read(WheelFeedbackSet& out) const = 0;
};

}  // namespace carril::hal
