#pragma once
// The robot target's wiring: every object of the robot build, created and connected here, top to
// bottom in the order data flows (clock and devices -> HAL -> firmware -> fixed-rate loop), and
// the firmware's task table on the robot.
#include <memory>

#include "firmware/app/FirmwareApp.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/LineFirmware.hpp"
#include "firmware/app/StatusReporter.hpp"
#include "firmware/core/EventLog.hpp"
#include "firmware/core/FixedRateLoop.hpp"
#include "firmware/core/SlowRateGroup.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Devices.hpp"
#include "hal/linux/LinuxClock.hpp"
#include "hal/linux/PeriodicThread.hpp"
#include "hal/linux/StdoutConsole.hpp"
#include "hal/null/NullDevices.hpp"

namespace carril::robot {

// The firmware's task table on the robot: which component runs at what rate (from the configured
// sensor rates), on which tick of its period, with what time budget.
fw::Status declare_tasks(fw::LineFirmware& fw);

// The slow rate group on the robot: work that must not delay the control loop (today the status
// line, an OS call; planning and localisation next), on its own thread at a lower priority
// (RobotTopology::start_slow_group), fed through the firmware's TripleBuffer.
constexpr double kSlowRateHz = 5.0;  // [Hz]
constexpr int kLoopPriority = 50;    // SCHED_FIFO priority of the control loop
constexpr int kSlowPriority = 10;    // and of the slow rate group, below it
fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              fw::EventSink& events);

// Large (the controller's latency histograms are a few hundred KiB): create it once, on the heap,
// at init, with create(). Neither copyable nor movable: the objects below hold references to each
// other.
struct RobotTopology {
  // The wired robot, or nullptr with `error` naming the field or task that is wrong.
  static std::unique_ptr<RobotTopology> create(const fw::FirmwareConfig& config, fw::Status& error);
  explicit RobotTopology(const fw::FirmwareConfig& config);
  RobotTopology(const RobotTopology&) = delete;
  RobotTopology& operator=(const RobotTopology&) = delete;

  // Time: CLOCK_MONOTONIC, absolute-deadline sleeps.
  hal::LinuxClock clock;
  // Devices. No CAN backend yet: null stand-ins that report "nothing there". The configuration
  // still says what the robot description says is fitted: a fitted lidar that never reports
  // holds the mission in START until its init timeout (scanner_timeout, or an earlier fault), and
  // a fitted IMU that gives no valid sample is not judged. So the robot never moves on a sensor it
  // cannot hear, and no C++ decides what the robot has.
  hal::NullCamera camera;
  hal::NullRangeScanner scanner;
  hal::NullImu imu;
  hal::NullWheelDrives drives;
  hal::Devices devices;
  // The firmware.
  fw::FirmwareConfig config;
  fw::LineFirmware firmware;
  fw::FirmwareApp app;
  // The fixed-rate loop that drives app.step().
  fw::FixedRateLoop loop;
  // The slow rate group, its console and its thread (started by start_slow_group()).
  hal::StdoutConsole console;
  fw::StatusReporter reporter;
  fw::EventLog<32> slow_events;  // written by the slow thread only; read after it stopped
  fw::SlowRateGroup slow;
  hal::PeriodicThread slow_thread;

  // Starts the slow group's thread, below the control loop's priority (`loop_is_fifo`: the loop
  // got SCHED_FIFO, so the group may too, lower). False with the reason in slow_thread.note().
  bool start_slow_group(bool loop_is_fifo);
};

}  // namespace carril::robot
