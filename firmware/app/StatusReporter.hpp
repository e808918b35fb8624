#pragma once
// Component of the slow rate group: the firmware's status line. The telemetry task (control
// loop) hands a snapshot over through a TripleBuffer, never waiting; the reporter, on the slow
// group (its own lower-priority thread on the robot, lockstep in the simulator), formats it and
// writes it to the console, so the control loop never makes that OS call.
#include <cstdint>

#include "firmware/core/Faults.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/mission/Mission.hpp"
#include "hal/Console.hpp"
#include "hal/TripleBuffer.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// What the control loop hands the slow group: small, copied whole.
struct StatusSnapshot {
  hal::TimeNs t_ns = 0;  // loop time [ns]
  std::uint64_t ticks = 0;
  std::uint64_t tick_overruns = 0;
  double tick_max_us = 0.0;  // [us]
  const char* state = "";
  const char* phase = "";
  MissionStatus status = MissionStatus::Starting;
  Fault fault = Fault::None;
  Pose2 odom;
  std::uint64_t frames = 0, scans = 0;  // new camera frames and scans seen
  std::uint64_t events_dropped = 0;
};

class StatusReporter {
 public:
  StatusReporter(hal::TripleBuffer<StatusSnapshot>& in, hal::Console& out) : in_(in), out_(out) {}

  // Slow task: writes the newest snapshot, if there is a new one, as one line.
  void run();
  std::uint64_t lines() const { return lines_; }

  // The line for `s` (at most n - 1 characters).
  static void format(const StatusSnapshot& s, char* buf, std::size_t n);

 private:
  hal::TripleBuffer<StatusSnapshot>& in_;
  hal::Console& out_;
  std::uint64_t lines_ = 0;
};

}  // namespace carril::fw
