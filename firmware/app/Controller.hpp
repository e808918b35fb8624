#pragma once
// The firmware's fixed-rate core: tick(SensorFrame) -> ActuatorCommand. All state is sized here
// at construction; a tick allocates nothing, blocks on nothing and makes no OS call (the clock
// is read only to time tasks).
#include <array>
#include <cstdint>

#include "firmware/core/Faults.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/Frames.hpp"
#include "firmware/behavior/BypassPlanner.hpp"
#include "firmware/behavior/MissionBehavior.hpp"
#include "firmware/behavior/MissionState.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/TaskTable.hpp"
#include "firmware/estimation/Odometry.hpp"
#include "firmware/health/SensorHealth.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "firmware/perception/LineDetector.hpp"
#include "firmware/perception/ObstacleField.hpp"
#include "firmware/perception/TapeMap.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

// Counters the firmware reports; refreshed by the telemetry task (and by refresh_telemetry()).
struct Telemetry {
  std::uint64_t ticks = 0;
  std::uint64_t tick_overruns = 0;  // ticks whose compute exceeded the tick budget
  double tick_budget_us = 0.0;
  double tick_p50_us = 0.0, tick_p99_us = 0.0, tick_max_us = 0.0;
  StaticVector<TaskCounters, TaskTable::kMaxTasks> tasks;
  MissionState state = MissionState::Start;
  const char* phase = "";
  Fault fault = Fault::None;  // latched fault, if any
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts{};
  std::uint32_t line_lost_events = 0;
  std::uint32_t line_reacquired_events = 0;
  std::uint32_t reversed_sightings = 0;  // tape seen backwards in SEARCH, and not followed
  std::uint32_t obstacles_avoided = 0;
  std::uint64_t invalid_beams = 0;   // NaN, inf, zero or out-of-limits lidar ranges seen
  double scan_valid_fraction = 1.0;  // valid beams over the lidar health window [0..1]
  int frame_spread = 0;              // colour spread of the last frame (0: one flat colour)
  std::uint64_t frames_processed = 0;
  Pose2 odom;
  bool end_done = false;  // stopped on the end mark
};

class Controller {
 public:
  static constexpr std::size_t kEventLog = 64;

  Controller(const FirmwareConfig& cfg, const hal::Clock& clock);
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;

  // One control period.
  ActuatorCommand tick(const SensorFrame& frame);

  MissionState state() const {
    return fault_ != Fault::None ? MissionState::Fault : behavior_.state();
  }
  const Telemetry& telemetry() const { return telemetry_; }
  void refresh_telemetry();
  // Events since the last drain, oldest first (outside the tick).
  RingBuffer<Event, kEventLog>& events() { return events_; }
  const LineDetection& detection() const { return det_; }
  const TapeMap& tape_map() const { return map_; }
  const FirmwareConfig& config() const { return cfg_; }
  double period_s() const { return period_s_; }

 private:
  void task_health();
  void task_odometry();
  void task_perception();
  void task_obstacles();
  void task_behavior();
  void task_telemetry();

  void log_state(MissionState from, MissionState to);
  // Latches fault `f` (the first one only), which struck in state `in_state`.
  void raise(Fault f, std::uint16_t code, MissionState in_state);
  double now_s() const { return double(frame_->now_ns) * 1e-9; }

  FirmwareConfig cfg_;
  const hal::Clock& clock_;
  double period_s_;
  DriveKinematics kin_;
  CameraModel cam_;
  LineDetector detector_;
  Odometry odom_;
  TapeMap map_;
  ObstacleField obstacles_;
  ScanHealth scan_health_;
  FrameHealth frame_health_;
  ImuHealth imu_health_;
  LineController line_;
  BypassPlanner planner_;
  MissionBehavior behavior_;
  MotionLimiter limiter_;
  TaskTable tasks_;
  LatencyStats tick_stats_;
  std::int64_t tick_budget_ns_;

  const SensorFrame* frame_ = nullptr;
  std::uint64_t tick_ = 0;
  ActuatorCommand cmd_;
  Telemetry telemetry_;
  RingBuffer<Event, kEventLog> events_;
  Fault fault_ = Fault::None;
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts_{};

  LineDetection det_;
  std::uint32_t last_frame_seq_ = 0;
  double last_frame_s_ = 0.0;
  bool fresh_frame_ = false;
  std::uint32_t last_scan_seq_ = 0;
  double last_scan_s_ = 0.0;
  bool fresh_scan_ = false;
  bool end_known_ = false;
  Vec2 end_odom_ = Vec2::Zero();
  std::uint64_t frames_processed_ = 0;
};

}  // namespace carril::fw
