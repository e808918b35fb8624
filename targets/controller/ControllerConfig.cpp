#include "targets/controller/ControllerConfig.hpp"

#include "loader/ControllerLoader.hpp"
#include "loader/FirmwareConfigBuilder.hpp"
#include "loader/MapMission.hpp"
#include "loader/MissionLoader.hpp"
#include "loader/OccupancyMapFile.hpp"
#include "loader/RobotLoader.hpp"
#include "loader/TuningLoader.hpp"

namespace carril::controller {

namespace {

// A mission on a known map (the mission file's map:): the map read into `grid` (sized to it, at
// init) and the firmware set up to localise on it, which takes a 2D lidar.
bool load_static_map(const ConfigFiles& files, LoadedConfig& l, std::string& error) {
  if (l.mission.map_path.empty()) return true;
  if (l.controller.lidar.source == loader::SensorSource::None) {
    error = std::string("--mission: ") + files.mission +
            ": map: localising on a map needs a 2D lidar, and " + l.controller.source_path +
            ": sensors.lidar.source is none";
    return false;
  }
  const loader::OccupancyMapLoad m =
      loader::load_occupancy_map(l.mission.map_path, loader::kMaxMapCells);
  if (!m.ok()) {
    error = std::string("--mission: ") + files.mission + ": map: cannot load the map: " + m.error;
    return false;
  }
  l.map = std::make_unique<fw::OccupancyGrid>(m.map.cells.size());
  if (const fw::Status st = l.map->assign(m.map.info, m.map.cells.data()); !st) {
    error = std::string("--mission: ") + files.mission + ": map: " + st.message();
    return false;
  }
  l.config.map = l.map.get();
  // Without an initial_pose the robot starts at the map's origin.
  loader::configure_for_map(l.robot, l.mission.localisation, {}, l.config);
  return true;
}

}  // namespace

bool load_controller_config(const ConfigFiles& files, LoadedConfig& l, std::string& error) {
  std::string e;
  if (!loader::load_robot_preset(files.robot, l.robot, e)) {
    error = "--robot: " + e;
    return false;
  }
  if (!loader::load_controller(files.controller, l.robot, l.controller, e)) {
    error = "--controller: " + e;
    return false;
  }
  if (!loader::load_mission(files.mission, l.robot, l.mission, e)) {
    error = "--mission: " + e;
    return false;
  }
  loader::Tuning tuning;
  if (files.tuning != nullptr && !loader::load_tuning(files.tuning, tuning, e)) {
    error = "--tuning: " + e;
    return false;
  }
  const loader::BuildResult built = loader::build_firmware_config(
      l.robot, l.mission, files.tuning != nullptr ? &tuning : nullptr);
  if (!built.ok) {
    error = "configuration: " + built.error;
    return false;
  }
  l.config = built.config;
  return load_static_map(files, l, error);
}

}  // namespace carril::controller
