#pragma once
// The one mapping from a robot description, a mission and optional component tuning to the
// firmware's configuration, used by the simulator (carril_sim) and the robot target
// (carril_controller) alike. Never throws.
#include <string>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"
#include "loader/TuningLoader.hpp"

namespace carril::loader {

struct BuildResult {
  bool ok = false;
  fw::FirmwareConfig config;  // valid when ok
  // Why not: "<file>[:<line>]: <key>: <problem>", naming where the rejected value was written.
  std::string error;
  std::string firmware_error;  // FirmwareConfig::validate()'s own message ("" when ok)
};

// The firmware's drive geometry for a robot [m].
fw::DriveGeometry drive_geometry(const RobotSpec& robot);

// The firmware's camera mount for a camera description (angles from deg to rad).
fw::CameraMount camera_mount(const CameraSpec& camera);

// Builds the configuration in stages, each validated: the robot's rate, geometry, limits, sensor
// mounts and rates and which sensors are fitted, with the mission's colours (detector windows),
// strategy and speed; then what follows from the rates (fw::apply_sensor_rates); then the
// mission's settings; then `tuning`'s (nullptr: none).
BuildResult build_firmware_config(const RobotSpec& robot, const MissionSpec& mission,
                                  const Tuning* tuning = nullptr);

}  // namespace carril::loader
