#pragma once
// In-process simulator backend. The simulator writes sensor data and reads setpoints here in
// lockstep with the physics; the firmware sees only the hal interfaces. No physics in here.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hal/Camera.hpp"
#include "hal/Clock.hpp"
#include "hal/Console.hpp"
#include "hal/Imu.hpp"
#include "hal/RangeScanner.hpp"
#include "hal/WheelDrives.hpp"

namespace carril::hal {

// Loop time is the simulated time the simulator sets; compute time is real.
class SimClock final : public Clock {
 public:
  TimeNs now_ns() const override { return now_ns_; }
  TimeNs cpu_now_ns() const override;
  // Lockstep: the simulator owns time, so waiting is a jump to the deadline.
  void sleep_until_ns(TimeNs t) override {
    if (t > now_ns_) now_ns_ = t;
  }
  // Simulator side: the physics has reached t [ns].
  void set_now_ns(TimeNs t) { now_ns_ = t; }

 private:
  TimeNs now_ns_ = 0;
};

// Faults a simulated sensor can be given. All but Silent keep the device publishing on time,
// so only the firmware's health rules (firmware/health) can tell.
enum class SimSensorFault : std::uint8_t {
  None,
  Silent,            // the device stops delivering (unplugged cable, dead driver)
  WrongSize,         // camera: frames arrive with a size the firmware was not configured for
  Frozen,            // camera: the same image again with every new frame; IMU: the same sample
  Blank,             // camera: every frame one flat colour (lens cap, blank capture buffers)
  NanRanges,         // lidar: every range NaN
  ZeroRanges,        // lidar: every range 0
  OutOfLimitRanges,  // lidar: every range beyond range_max_m (finite)
  OutOfRange,        // IMU: a yaw rate no robot on a floor turns at, and a NaN roll
};

class SimCamera final : public Camera {
 public:
  SimCamera();
  const CameraFrame* latest() override;
  // Simulator side: the buffer to render into, then publish() it with its stamp.
  CameraFrame& back_buffer() { return *frame_; }
  // Whether the back buffer still holds what was last rendered into it: no fault has written to
  // it or resized it since (a renderer may then redraw only what changes).
  bool back_buffer_as_rendered() const { return as_rendered_; }
  void publish(TimeNs stamp_ns);
  void inject_fault(SimSensorFault f) { fault_ = f; }

 private:
  std::unique_ptr<CameraFrame> frame_;   // sized once at construction (3.7 MB)
  std::unique_ptr<CameraFrame> frozen_;  // the image a Frozen camera repeats
  bool frozen_taken_ = false;
  bool as_rendered_ = false;
  std::uint32_t seq_ = 0;
  SimSensorFault fault_ = SimSensorFault::None;
};

class SimRangeScanner final : public RangeScanner {
 public:
  SimRangeScanner();
  const LaserScan* latest() override;
  LaserScan& back_buffer() { return *scan_; }
  void publish(TimeNs stamp_ns);
  void inject_fault(SimSensorFault f) { fault_ = f; }

 private:
  std::unique_ptr<LaserScan> scan_;
  std::uint32_t seq_ = 0;
  SimSensorFault fault_ = SimSensorFault::None;
};

// Console that keeps every line (the simulator's slow rate group runs in lockstep on the
// simulator's thread; the run reads the lines afterwards).
class SimConsole final : public Console {
 public:
  void write_line(const char* line) override { lines_.emplace_back(line); }
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  std::vector<std::string> lines_;
};

class SimImu final : public Imu {
 public:
  ImuSample read() override { return fault_ == SimSensorFault::Silent ? ImuSample{} : sample_; }
  // Simulator side: the newest measurement (a Frozen IMU keeps handing out the old one).
  void publish(const ImuSample& s);
  // Silent, Frozen or OutOfRange.
  void inject_fault(SimSensorFault f) { fault_ = f; }

 private:
  ImuSample sample_{};
  SimSensorFault fault_ = SimSensorFault::None;
};

// Emulates the drive side of the CiA 402 state machine: enable takes one bus sync, quick stop
// and faults latch, setpoints only count while Enabled. sync() is the simulated bus transfer: the
// simulator applies only what was latched there, so setpoints the firmware set but did not sync
// never reach the motors.
class SimWheelDrives final : public WheelDrives {
 public:
  explicit SimWheelDrives(int count);
  // Ok (a simulated bus has nothing to bring up) unless fail_init() set a failure.
  DriveInitResult init() override;
  int count() const override { return count_; }
  void enable() override;
  void disable() override;
  void quick_stop() override;
  void reset_faults() override;
  void set_velocity(const float* radps, int n) override;
  // Advance each drive's state machine one sync and latch the velocity its motor is asked for
  // (the staged setpoint while Enabled, else zero).
  void sync() override;
  void read(WheelFeedbackSet& out) const override;

  // Simulator side, after the firmware's step: the velocity each wheel motor was asked for at
  // the last sync(), count() values [rad/s].
  void take_setpoints(float* target_radps) const;
  // Simulator side: what the wheels actually did.
  void set_feedback(int wheel, TimeNs stamp_ns, float velocity_radps, double position_rad);
  void inject_fault(int wheel, DriveFault code);
  // Test side: every later init() fails, naming drive `wheel` (-1: no one drive) and `what`.
  void fail_init(int wheel, const char* what);
  DriveState state(int wheel) const { return fb_.wheel[wheel].state; }
  int quick_stop_requests() const { return quick_stops_; }
  // Number of sync() calls so far: the firmware's periods, if it syncs once per period.
  std::uint64_t syncs() const { return syncs_; }

 private:
  int count_;
  WheelFeedbackSet fb_{};
  std::array<float, kMaxWheels> setpoint_{};  // staged by set_velocity()
  std::array<float, kMaxWheels> latched_{};   // taken at sync(): what the motors follow
  // Per drive, as on a bus: a fault cancels that drive's request, so recovery needs a new enable.
  std::array<bool, kMaxWheels> enable_requested_{};
  int quick_stops_ = 0;
  std::uint64_t syncs_ = 0;
  DriveInitResult init_result_{};
};

}  // namespace carril::hal
