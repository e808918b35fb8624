#pragma once
// The robot target's wiring: every object of the robot build, created and connected here, top to
// bottom in the order data flows (clock and devices -> HAL -> firmware -> fixed-rate loop).
#include "firmware/app/Controller.hpp"
#include "firmware/app/FirmwareApp.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/core/FixedRateLoop.hpp"
#include "hal/Devices.hpp"
#include "hal/linux/LinuxClock.hpp"
#include "hal/null/NullDevices.hpp"

namespace carril::robot {

// Firmware configuration of the robot (campero's values from config/robots/campero.yaml,
// hardcoded: the target has no YAML reader yet).
fw::FirmwareConfig robot_config();

// Large (the controller's latency histograms are a few hundred KiB): create it once, on the heap,
// at init. Neither copyable nor movable: the objects below hold references to each other.
struct RobotTopology {
  RobotTopology();
  RobotTopology(const RobotTopology&) = delete;
  RobotTopology& operator=(const RobotTopology&) = delete;

  // Time: CLOCK_MONOTONIC, absolute-deadline sleeps.
  hal::LinuxClock clock;
  // Devices. No CAN backend yet: null stand-ins that report "nothing there".
  hal::NullCamera camera;
  hal::NullRangeScanner scanner;
  hal::NullImu imu;
  hal::NullWheelDrives drives;
  hal::Devices devices;
  // The firmware.
  fw::FirmwareConfig config;
  fw::Controller controller;
  fw::FirmwareApp app;
  // The fixed-rate loop that drives app.step().
  fw::FixedRateLoop loop;
};

}  // namespace carril::robot
