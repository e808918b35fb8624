#pragma once
// Data types that cross the HAL: what real drivers and the simulator both produce.
#include <array>
#include <cstdint>

namespace carril::hal {

using TimeNs = std::int64_t;  // monotonic time [ns]

constexpr int kMaxWheels = 4;
constexpr int kMaxImageWidth = 1280;
constexpr int kMaxImageHeight = 960;
constexpr int kMaxScanBeams = 2048;

// Colour image, 3 bytes per pixel in B,G,R order (what V4L2/OpenCV capture gives), row-major.
struct CameraFrame {
  std::uint32_t seq = 0;     // increments with every new frame; 0 = no frame yet
  TimeNs stamp_ns = 0;       // exposure time [ns]
  std::uint16_t width = 0;   // [px]
  std::uint16_t height = 0;  // [px]
  std::array<std::uint8_t, std::size_t{kMaxImageWidth} * kMaxImageHeight * 3> bgr{};

  const std::uint8_t* pixel(int u, int v) const { return &bgr[(std::size_t(v) * width + u) * 3]; }
  std::uint8_t* pixel(int u, int v) { return &bgr[(std::size_t(v) * width + u) * 3]; }
};

// One 2D lidar sweep. Ranges follow ROS REP 117: +inf = no return within range_max_m, -inf =
// something closer than range_min_m, NaN = an invalid measurement; drivers also report 0 or
// out-of-limit values for invalid beams. Consumers must check std::isfinite before comparing.
struct LaserScan {
  std::uint32_t seq = 0;                        // 0 = no scan yet
  TimeNs stamp_ns = 0;                          // [ns]
  float angle_min_rad = 0.0F;                   // first beam, in the sensor frame [rad]
  float angle_increment_rad = 0.0F;             // [rad]
  float range_min_m = 0.0F;                     // [m]
  float range_max_m = 0.0F;                     // [m]
  std::uint16_t count = 0;                      // beams in ranges_m
  std::array<float, kMaxScanBeams> ranges_m{};  // [m]
};

struct ImuSample {
  TimeNs stamp_ns = 0;  // [ns]
  bool valid = false;
  float roll_rad = 0.0F;        // [rad]
  float pitch_rad = 0.0F;       // [rad]
  float yaw_rate_radps = 0.0F;  // [rad/s]
};

// Drive state, modelled on the CiA 402 power state machine seen from the master.
enum class DriveState : std::uint8_t {
  Disabled,   // not powered (Switch on disabled / Ready to switch on)
  Enabling,   // enable requested, sequence under way
  Enabled,    // Operation enabled: follows velocity setpoints
  QuickStop,  // Quick stop active: braking to zero, ignores setpoints
  Fault,      // Fault: needs fault_reset
};

// Fault codes (CiA 301/402 error code style; 0 = none).
enum class DriveFault : std::uint16_t {
  None = 0,
  HeartbeatLost = 0x8130,  // no heartbeat from the drive within its timeout
  Overcurrent = 0x2310,
  Undervoltage = 0x3220,
  FollowingError = 0x8611,
  Internal = 0x6000,
};

struct WheelFeedback {
  TimeNs stamp_ns = 0;          // when the drive sampled it [ns]
  float velocity_radps = 0.0F;  // measured wheel speed [rad/s]
  double position_rad = 0.0;    // accumulated encoder angle [rad]
  DriveState state = DriveState::Disabled;
  DriveFault fault = DriveFault::None;
};

struct WheelFeedbackSet {
  std::uint8_t count = 0;
  std::array<WheelFeedback, kMaxWheels> wheel{};
};

}  // namespace carril::hal
