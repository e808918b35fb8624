#pragma once
// The firmware's fixed-rate core: tick(SensorFrame) -> ActuatorCommand. All state is sized here
// at construction; a tick allocates nothing, blocks on nothing and makes no OS call (the clock
// is read only to time tasks).
#include <array>
#include <cstdint>

#include "firmware/app/Faults.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/Frames.hpp"
#include "firmware/behavior/MissionState.hpp"
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/control/PursuitFollower.hpp"
#include "firmware/core/LatencyStats.hpp"
#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/TaskTable.hpp"
#include "firmware/estimation/Odometry.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "firmware/perception/TapeScanner.hpp"
#include "hal/Clock.hpp"

namespace carril::fw {

// Counters the firmware reports; refreshed by the telemetry task (and by refresh_telemetry()).
struct Telemetry {
  std::uint64_t ticks = 0;
  std::uint64_t tick_overruns = 0;  // ticks whose compute exceeded the tick budget
  double tick_budget_us = 0.0;
  double tick_p50_us = 0.0, tick_p99_us = 0.0, tick_max_us = 0.0;
  StaticVector<TaskCounters, TaskTable::kMaxTasks> tasks;
  MissionState state = MissionState::Init;
  Fault fault = Fault::None;  // latched fault, if any
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts{};
  std::uint32_t line_lost_events = 0;
  std::uint32_t line_reacquired_events = 0;
  std::uint32_t obstacles_avoided = 0;
  std::uint32_t protective_stops = 0;
  std::uint64_t invalid_beams = 0;  // NaN, inf, zero or out-of-limits lidar ranges seen
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

  MissionState state() const { return state_; }
  const Telemetry& telemetry() const { return telemetry_; }
  void refresh_telemetry();
  // Events since the last drain, oldest first (outside the tick).
  RingBuffer<Event, kEventLog>& events() { return events_; }
  const TapeObservation& observation() const { return obs_; }
  const FirmwareConfig& config() const { return cfg_; }
  double period_s() const { return period_s_; }

 private:
  void task_health();
  void task_odometry();
  void task_perception();
  void task_obstacles();
  void task_behavior();
  void task_telemetry();

  void set_state(MissionState s);
  void raise(Fault f, std::uint16_t code = 0);
  double now_s() const { return double(frame_->now_ns) * 1e-9; }
  double in_state_s() const { return now_s() - state_since_s_; }

  FirmwareConfig cfg_;
  const hal::Clock& clock_;
  double period_s_;
  DriveKinematics kin_;
  CameraModel cam_;
  TapeScanner scanner_;
  Odometry odom_;
  PursuitFollower follower_;
  MotionLimiter limiter_;
  TaskTable tasks_;
  LatencyStats tick_stats_;
  std::int64_t tick_budget_ns_;

  const SensorFrame* frame_ = nullptr;
  std::uint64_t tick_ = 0;
  ActuatorCommand cmd_;
  Telemetry telemetry_;
  RingBuffer<Event, kEventLog> events_;

  MissionState state_ = MissionState::Init;
  double state_since_s_ = 0.0;
  Fault fault_ = Fault::None;
  std::array<std::uint32_t, std::size_t(Fault::Count)> fault_counts_{};

  TapeObservation obs_;
  std::uint32_t last_frame_seq_ = 0;
  double last_frame_s_ = 0.0;
  bool fresh_obs_ = false;  // obs_ came from a frame processed this tick
  int frames_without_line_ = 0;
  double last_line_side_ = 1.0;  // +1 left, -1 right: where the tape was last seen
  std::uint32_t last_scan_seq_ = 0;
  double last_scan_s_ = 0.0;
  bool obstacle_ahead_ = false;
  double clear_since_s_ = 0.0;
  double search_start_yaw_ = 0.0, search_turned_ = 0.0;
  Vec2 end_mark_odom_ = Vec2::Zero();
  bool end_done_ = false;
  std::uint32_t line_lost_ = 0, line_reacquired_ = 0, protective_stops_ = 0;
  std::uint64_t invalid_beams_ = 0, frames_processed_ = 0;
};

}  // namespace carril::fw
