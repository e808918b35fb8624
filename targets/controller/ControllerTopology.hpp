#pragma once
// carril_controller's wiring: every object of the robot build, created and connected here, top
// to bottom in the order data flows (clock -> CAN bus -> CANopen drives and sensor links -> HAL
// devices -> firmware -> fixed-rate loop), and the firmware's task tables on the robot. What is
// fitted comes from the files (robot description, controller file), never from C++.
#include <memory>
#include <string>

#include "firmware/app/Firmware.hpp"
#include "firmware/app/FirmwareApp.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/StatusReporter.hpp"
#include "firmware/core/EventLog.hpp"
#include "firmware/core/FixedRateLoop.hpp"
#include "firmware/core/SlowRateGroup.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Devices.hpp"
#include "hal/can/CanLogTap.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"
#include "hal/linux/LinuxClock.hpp"
#include "hal/linux/PeriodicThread.hpp"
#include "hal/linux/ScipLidar.hpp"
#include "hal/linux/ShmSensorLink.hpp"
#include "hal/linux/SocketCanBus.hpp"
#include "hal/linux/StdoutConsole.hpp"
#include "hal/null/NullDevices.hpp"
#include "loader/ControllerSpec.hpp"
#include "targets/controller/CanLogFile.hpp"
#include "targets/controller/LoopReport.hpp"

namespace carril::controller {

// The slow rate group on the robot: work that must not delay the control loop (the status line,
// an OS call), on its own thread at a lower priority, fed through the firmware's TripleBuffer.
constexpr double kSlowRateHz = 5.0;  // [Hz]
constexpr int kSlowPriority = 10;    // SCHED_FIFO priority of the slow rate group, below the loop
fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              LoopReportPrinter& loop_report, CanLogFile& can_log,
                              fw::EventSink& events);

// The CANopen master's configuration from the controller file, for a control loop at
// `rate_hz` [Hz].
// max_wheel_radps: the robot's wheel speed limit; feedback beyond 1.5 times it is implausible.
hal::canopen::CanopenConfig canopen_config(const loader::ControllerSpec& spec, double rate_hz,
                                           double max_wheel_radps);

// The hardware side, opened before the firmware exists: the CAN bus and its drives, the sensor
// links. Members are null where the controller file says "none".
struct Hardware {
  // Opens everything the controller file names. False, with `error` naming the interface,
  // address or shared memory object and what is wrong.
  bool open(const loader::ControllerSpec& spec, const fw::FirmwareConfig& fw,
            const char* can_log_path, std::string& error);

  hal::LinuxClock clock;
  // CAN: the raw socket, optionally tapped for the candump log, under the CANopen master.
  std::unique_ptr<hal::SocketCanBus> socket;
  std::unique_ptr<hal::CanLogTap> tap;
  std::unique_ptr<hal::canopen::ClockSleepWaiter> waiter;
  std::unique_ptr<hal::canopen::CanopenWheelDrives> can_drives;
  std::unique_ptr<hal::NullWheelDrives> null_drives;  // can.interface: none (a bench run)
  // Sensors.
  std::unique_ptr<hal::ScipLidar> lidar;
  std::unique_ptr<hal::ShmSensorReader> camera_link;
  std::unique_ptr<hal::ShmSensorReader> imu_link;  // null when the camera's link carries it
  hal::NullCamera null_camera;
  hal::NullRangeScanner null_scanner;
  hal::NullImu null_imu;

  hal::WheelDrives& drives();
  hal::Camera& camera();
  hal::RangeScanner& scanner();
  hal::Imu& imu();
  // What each device is, for the start-up banner.
  std::string describe() const;

 private:
  bool imu_from_camera_link_ = false;  // one shared memory object carries camera and IMU
};

// Large (the controller's latency histograms are a few hundred KiB): create it once, on the heap,
// at init, with create(). Neither copyable nor movable: the objects below hold references to each
// other.
struct ControllerTopology {
  // The wired robot, or nullptr with `error` naming the field or task that is wrong.
  static std::unique_ptr<ControllerTopology> create(const fw::FirmwareConfig& config, Hardware& hw,
                                                    fw::Status& error);
  ControllerTopology(const fw::FirmwareConfig& config, Hardware& hw);
  ControllerTopology(const ControllerTopology&) = delete;
  ControllerTopology& operator=(const ControllerTopology&) = delete;

  Hardware& hw;
  hal::Devices devices;
  // The firmware.
  fw::FirmwareConfig config;
  fw::Firmware firmware;
  fw::FirmwareApp app;
  // The fixed-rate loop that drives app.step(): CLOCK_MONOTONIC, absolute deadlines.
  fw::FixedRateLoop loop;
  // The slow rate group, its console and its thread (started by start_slow_group()).
  hal::StdoutConsole console;
  fw::StatusReporter reporter;
  hal::TripleBuffer<LoopFigures> loop_figures;  // published by the loop on SIGUSR1
  LoopReportPrinter loop_report;
  CanLogFile can_log;            // --can-log: opened by main when asked
  fw::EventLog<32> slow_events;  // written by the slow thread only; read after it stopped
  fw::SlowRateGroup slow;
  hal::PeriodicThread slow_thread;

  // Starts the slow group's thread, below the control loop's priority (`loop_is_fifo`: the loop
  // got SCHED_FIFO, so the group may too, lower). False with the reason in slow_thread.note().
  bool start_slow_group(bool loop_is_fifo);
};

}  // namespace carril::controller
