#pragma once
#include <cstdarg>
#include <cstdio>

#include "hal/Types.hpp"

namespace carril::hal {

// The outcome of WheelDrives::init(): ok, or which drive failed and why, in fixed-size text (no
// heap; init runs where exceptions are off).
struct DriveInitResult {
  static constexpr int kMaxText = 256;  // the longest configuration error with its prefix is 174

  bool ok = true;
  int drive = -1;            // index of the drive that failed; -1 none, or not one drive
  char what[kMaxText] = {};  // "drive 2 (rear-left): no boot-up within 1.0 s"; "" when ok

  // Every drive is up.
  static DriveInitResult success() { return {}; }
  // printf-style reason; `drive` is the failing index or -1.
  [[gnu::format(printf, 2, 3)]] static DriveInitResult failure(int drive, const char* fmt, ...) {
    DriveInitResult r;
    r.ok = false;
    r.drive = drive;
    std::va_list args;
    va_start(args, fmt);
    std::vsnprintf(r.what, kMaxText, fmt, args);
    va_end(args);
    if (r.what[0] == '\0') r.what[0] = '?';  // a failure always says something
    return r;
  }
};

// Per-wheel velocity drives. Shaped after CiA 402 profile velocity mode: commands are requests
// that take effect through the drive's state machine (enable sequence, quick stop, fault reset);
// feedback reports what each drive actually did. Wheel order is fixed by the robot's kinematics
// (front-left, front-right, rear-left, rear-right; differential: left, right).
//
// One control period, as FirmwareApp::step() runs it: read() -> tick -> requests (enable,
// quick_stop, disable) -> set_velocity() -> sync(). Setpoints are only staged until sync(), the
// period's bus transfer; the enable sequence advances at syncs.
class WheelDrives {
 public:
  virtual ~WheelDrives() = default;
  // Bring the drives up (bus, boot-up, configuration); once, before the first tick. May block.
  virtual DriveInitResult init() = 0;
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
  // Velocity setpoints, one per wheel, applied at the next sync() [rad/s].
  virtual void set_velocity(const float* radps, int n) = 0;
  // End of the period's commands: exactly once per control period, after that period's requests
  // and set_velocity(), so a bus backend sends its PDOs and SYNC at one fixed point of the
  // period (drives apply what they got at SYNC). Non-blocking.
  virtual void sync() = 0;
  // Latest feedback from every drive.
  virtual void read(WheelFeedbackSet& out) const = 0;
};

}  // namespace carril::hal
