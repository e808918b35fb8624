#pragma once
// The simulator target's wiring: every object of a simulated robot, created and connected here,
// top to bottom in the order data flows (world -> sensors -> HAL -> firmware -> drives -> world),
// and the firmware's task table for this target.
#include <cstdint>
#include <functional>
#include <memory>

#include "firmware/app/Firmware.hpp"
#include "firmware/app/FirmwareApp.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/app/StatusReporter.hpp"
#include "firmware/core/EventLog.hpp"
#include "firmware/core/SlowRateGroup.hpp"
#include "hal/Devices.hpp"
#include "hal/sim/SimDevices.hpp"
#include "hal/sim/SimPointCloud.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/sensors/CameraRenderer.hpp"
#include "host_sim/sensors/GyroSim.hpp"
#include "host_sim/sensors/Lidar3dSim.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/sensors/WheelEncoderSim.hpp"
#include "host_sim/world/SimWorld.hpp"

namespace carril::sim {

// Firmware configuration for the robot and mission a scenario describes. With a map, `map` is
// the static map the firmware is given (filled from the scenario's; it must outlive the
// firmware), goals stay in the world frame (the map frame) and localisation starts at the
// scenario's initial pose; without one, goals are carried into the odometry frame.
fw::FirmwareConfig firmware_config(const Scenario& s, fw::OccupancyGrid* map = nullptr,
                                   std::uint64_t seed = 1);

// Changes the firmware configuration after it is derived from the scenario (tests: a rule
// switched off, to show what it guards against).
using ConfigTweak = std::function<void(fw::FirmwareConfig&)>;

// The slow rate group on the simulator: heavy or OS-bound work off the control loop, run in
// lockstep (SimRun calls its cycle every slow_divisor ticks), so runs stay bit-identical.
constexpr double kSlowRateHz = 5.0;  // [Hz]
fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              fw::EventSink& events);

struct SimTopology {
  // Throws std::invalid_argument, naming the field, when the configuration or the task table
  // is invalid.
  SimTopology(const Scenario& scenario, std::uint64_t seed, const ConfigTweak& tweak = {});

  const Scenario& scenario;
  // The physical world and the simulated sensors that observe it.
  SimWorld world;
  CameraRenderer camera_renderer;
  LidarSim lidar;
  WheelEncoderSim encoders;             // the wheel readings, with the scenario's odometry drift
  GyroSim gyro;                         // the IMU's yaw rate, with the robot's gyro errors
  std::unique_ptr<Lidar3dSim> lidar3d;  // only when the firmware maps terrain with it
  // The HAL backends the firmware sees (filled by the simulator in lockstep).
  hal::SimClock clock;
  hal::SimCamera camera;
  hal::SimRangeScanner scanner;
  hal::SimImu imu;
  hal::SimPointCloud cloud;
  hal::SimWheelDrives drives;
  hal::Devices devices;
  // The firmware.
  fw::OccupancyGrid static_map;  // the scenario's map as the firmware gets it (empty without)
  fw::FirmwareConfig config;
  std::unique_ptr<fw::Firmware> firmware;  // large (latency histograms): on the heap, at init
  fw::FirmwareApp app;
  // The slow rate group and what it runs.
  hal::SimConsole console;
  fw::StatusReporter reporter;
  fw::EventLog<32> slow_events;
  fw::SlowRateGroup slow;
  std::uint32_t slow_divisor = 1;  // the group's cycle runs every this many ticks
};

}  // namespace carril::sim
