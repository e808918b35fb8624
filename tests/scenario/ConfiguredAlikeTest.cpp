// Issue 47 item 4: the simulator and the robot are configured alike. The same robot description,
// mission and map, read once through carril_sim's path (a scenario, SimTopology's
// firmware_config) and once through carril_controller's (its robot, controller and mission files,
// ControllerConfig), give equal firmware configurations: no target sets tuning in its wiring.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "host_sim/app/SimTopology.hpp"
#include "targets/controller/ControllerConfig.hpp"
#include "tests/scenario/ScenarioSupport.hpp"

namespace carril::sim {
namespace {

namespace fs = std::filesystem;

std::string source(const std::string& rel) {
  return std::string(CARRIL_SOURCE_DIR) + "/" + rel;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("carril_alike_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

bool same_map(const fw::OccupancyGrid& a, const fw::OccupancyGrid& b) {
  const fw::MapInfo& x = a.info();
  const fw::MapInfo& y = b.info();
  if (x.nx != y.nx || x.ny != y.ny || x.resolution_m != y.resolution_m ||
      x.origin_x_m != y.origin_x_m || x.origin_y_m != y.origin_y_m) {
    return false;
  }
  return std::equal(a.data(), a.data() + std::size_t(x.nx) * std::size_t(x.ny), b.data());
}

// The controller's configuration from its files (the controller file for `robot`).
controller::LoadedConfig robot_target(const std::string& robot, const std::string& mission_file) {
  controller::LoadedConfig l;
  std::string error;
  const std::string r = source("config/robots/" + robot + ".yaml");
  const std::string c = source("config/controller/" + robot + ".yaml");
  EXPECT_TRUE(
      controller::load_controller_config({r.c_str(), c.c_str(), mission_file.c_str()}, l, error))
      << error;
  return l;
}

TEST(ConfiguredAlike, AGotoOnAMapIsTheSameConfigurationOnBothTargets) {
  for (const char* robot : {"campero"}) {  // the shipped controller file with a lidar
    SCOPED_TRACE(robot);
    const std::string map = source("scenarios/maps/house.yaml");
    const std::string mission = write_temp("goto_house.yaml", "type: goto\nmap: " + map + R"(
localisation:
  initial_pose: {x: 0.8, y: -0.5, yaw_deg: 30.0}
  initial_sigma_xy_m: 1.0
  initial_sigma_yaw_deg: 40.0
  recovery: true
goals:
  - {x: -2.6, y: -1.55, yaw_deg: 0}
  - {x: 3.6, y: 1.4, yaw_deg: 90}
speed_mps: 0.4
)");
    const Scenario s = test::load_yaml("name: alike\nduration_s: 60\nseed: 1\nmap: " + map +
                                       "\nrobot:\n  preset: " + robot + R"(
  start: {x: 0.0, y: 0.0, yaw_deg: 0.0}
localisation:
  initial_pose: {x: 0.8, y: -0.5, yaw_deg: 30.0}
  initial_sigma_xy_m: 1.0
  initial_sigma_yaw_deg: 40.0
  recovery: true
mission:
  type: goto
  goals:
    - {x: -2.6, y: -1.55, yaw_deg: 0}
    - {x: 3.6, y: 1.4, yaw_deg: 90}
  speed_mps: 0.4
)");
    fw::OccupancyGrid sim_map;
    fw::FirmwareConfig sim = firmware_config(s, &sim_map, 1);  // the robot's seed is 1 too
    controller::LoadedConfig ctl = robot_target(robot, mission);
    ASSERT_NE(ctl.map, nullptr);
    EXPECT_TRUE(same_map(sim_map, *ctl.map));
    sim.map = ctl.config.map = nullptr;  // two copies of one map, compared above
    EXPECT_TRUE(sim == ctl.config);
    // The localiser's model is the robot file's on both, not the firmware's defaults.
    EXPECT_EQ(ctl.config.localisation.mcl.sigma_hit_m, 0.1);
    EXPECT_TRUE(ctl.config.localisation.mcl.surface_distance);
    EXPECT_EQ(ctl.config.localisation.mcl.search_sigma_hit_m, 0.2);
    // And the comparison sees one field apart.
    fw::FirmwareConfig other = ctl.config;
    other.tasks.mission_us += 1.0;
    EXPECT_FALSE(sim == other);
  }
}

TEST(ConfiguredAlike, AFollowLineMissionIsTheSameConfigurationOnBothTargets) {
  const std::string mission = write_temp("follow_line.yaml", R"(type: follow_line
strategy: marks
line_color: white
end_color: yellow
speed_mps: 0.5
)");
  const Scenario s = test::load_repo_scenario("square");  // campero, the same mission
  const fw::FirmwareConfig sim = firmware_config(s, nullptr, 1);
  const controller::LoadedConfig ctl = robot_target("campero", mission);
  EXPECT_TRUE(sim == ctl.config);
}

}  // namespace
}  // namespace carril::sim
