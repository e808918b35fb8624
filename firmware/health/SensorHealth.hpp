#pragma once
// Sensor health: rules that tell a blind or stuck sensor from a working one, for sensors that
// keep publishing on time (so the timeouts never fire) but whose data no longer says anything:
// a lidar whose ranges are all NaN, zero or out of limits; a camera whose frames are one flat
// colour (lens cap, a capture driver handing out blank buffers) or repeat the same image while
// the wheels say the robot moves; an IMU whose sample no longer changes, or reads what no robot
// on a floor can do. Each monitor is fed one sample at a time and says whether the rule broke.
// No heap, no OS: they run inside the tick.
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct ScanHealthConfig {
  int window_scans = 5;              // scans the valid-beam fraction is taken over
  double min_valid_fraction = 0.05;  // fewer valid beams than this over the window: blind [0..1]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<ScanHealthConfig>> params();
  Status validate() const;
  bool operator==(const ScanHealthConfig&) const = default;
};

// Lidar: a beam is valid when it is a measurement: a range within [range_min, range_max], +inf
// (nothing within range) or -inf (something closer than range_min), the REP 117 convention.
// NaN, zero, negative and finite out-of-limit ranges are not: a scan made of them says nothing.
// (A dead laser that reports +inf everywhere looks like an empty hall; that takes the scanner's
// own diagnostics.)
class ScanHealth {
 public:
  static constexpr int kMaxWindow = 64;
  explicit ScanHealth(const ScanHealthConfig& cfg);
  // Adds one scan; returns false once the window is full and its valid fraction is too low.
  bool add(const hal::LaserScan& scan);
  double valid_fraction() const;  // over the current window; 1 when empty

 private:
  struct Count {
    std::uint32_t valid = 0, total = 0;
  };
  ScanHealthConfig cfg_;
  RingBuffer<Count, kMaxWindow> window_;
};

struct FrameHealthConfig {
  int sample_step_px = 8;         // every this many pixels in both directions is looked at
  int blank_tolerance = 6;        // spread (max - min) per channel at or below this: one colour
  int blank_frames = 6;           // consecutive blank frames before the fault
  double frozen_motion_m = 0.05;  // the image may not stay identical over this much travel [m]
  double frozen_turn_rad = 0.05;  // ... or this much turning [rad]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<FrameHealthConfig>> params();
  Status validate() const;
  bool operator==(const FrameHealthConfig&) const = default;
};

enum class FrameVerdict : std::uint8_t { Ok, Blank, Frozen };

// Camera: looks at a sparse grid of the frame for its colour spread and a content hash.
class FrameHealth {
 public:
  explicit FrameHealth(const FrameHealthConfig& cfg) : cfg_(cfg) {}
  // Adds one frame seen at odometry pose `odom`.
  FrameVerdict add(const hal::CameraFrame& frame, const Pose2& odom);
  std::uint64_t last_hash() const { return hash_; }
  int last_spread() const { return spread_; }  // largest per-channel spread of the last frame

 private:
  FrameHealthConfig cfg_;
  std::uint64_t hash_ = 0;
  bool have_hash_ = false;
  int spread_ = 0;
  int blank_run_ = 0;
  Pose2 changed_at_;  // odometry pose when the image content last changed
};

struct ImuHealthConfig {
  double max_tilt_rad = 0.6;        // |roll| or |pitch| beyond this: not a robot on a floor [rad]
  double max_yaw_rate_radps = 6.0;  // |yaw rate| beyond this: impossible for the robot [rad/s]
  int out_of_range_samples = 3;     // consecutive implausible samples before the fault
  double frozen_s = 0.5;            // a sample (stamp and values) may not repeat this long [s]
  double frozen_min_turn_change_radps = 0.2;  // odometry yaw rate change the IMU must follow

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<ImuHealthConfig>> params();
  Status validate() const;
  bool operator==(const ImuHealthConfig&) const = default;
};

enum class ImuVerdict : std::uint8_t { Ok, OutOfRange, Frozen };

// IMU: out of range (NaN, inf or beyond what the robot can do), or frozen: the same sample
// handed out again and again (same stamp), or the same values while the odometry's yaw rate
// changed by more than the IMU can miss.
class ImuHealth {
 public:
  explicit ImuHealth(const ImuHealthConfig& cfg) : cfg_(cfg) {}
  // Adds the sample read at loop time `t_s`, with the odometry's yaw rate then [rad/s].
  ImuVerdict add(const hal::ImuSample& s, double t_s, double odom_yaw_rate_radps);

 private:
  ImuHealthConfig cfg_;
  int bad_run_ = 0;
  bool have_last_ = false;
  hal::ImuSample last_{};
  double same_since_s_ = 0.0;                     // when the current sample (values) was first seen
  double stamp_since_s_ = 0.0;                    // when the current stamp was first seen
  double odom_wz_min_ = 0.0, odom_wz_max_ = 0.0;  // odometry yaw rates since the values froze
};

}  // namespace carril::fw
