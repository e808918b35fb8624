#pragma once
// The robot target's configuration path: its four files (robot description, controller file,
// mission, optional tuning) and the mission's map into one fw::FirmwareConfig, through the same
// loader as the simulator's. In a library of its own so that a test can build the configuration
// through both targets' paths from the same files and compare them.
#include <memory>
#include <string>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "loader/ControllerSpec.hpp"
#include "loader/MissionSpec.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::controller {

// The files carril_controller is given (tuning may be null: none).
struct ConfigFiles {
  const char* robot = nullptr;
  const char* controller = nullptr;
  const char* mission = nullptr;
  const char* tuning = nullptr;
};

// What the files hold, and the firmware configuration built from them (not yet validated: the
// caller validates it). map holds the mission's map (sized at init) when it names one; it must
// outlive every firmware built from `config`.
struct LoadedConfig {
  loader::RobotSpec robot;
  loader::ControllerSpec controller;
  loader::MissionSpec mission;
  std::unique_ptr<fw::OccupancyGrid> map;
  fw::FirmwareConfig config;
};

// False with `error` ("--robot: <file>: <key>: ...") naming the option, the file and the key.
bool load_controller_config(const ConfigFiles& files, LoadedConfig& out, std::string& error);

}  // namespace carril::controller
