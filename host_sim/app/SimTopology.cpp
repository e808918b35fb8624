#include "host_sim/app/SimTopology.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "host_sim/app/CostmapOutputs.hpp"
#include "loader/FirmwareConfigBuilder.hpp"
#include "loader/MapMission.hpp"
#include "loader/OccupancyMapFile.hpp"

namespace carril::sim {

namespace {
using fw::kPi;  // the one pi, firmware/core/Geometry.hpp
constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}
}  // namespace

fw::FirmwareConfig firmware_config(const Scenario& s, fw::OccupancyGrid* map, std::uint64_t seed) {
  // The same builder as the robot target's; a rejection reads as SimTopology's own would.
  loader::BuildResult b = loader::build_firmware_config(s.robot, s.mission);
  if (!b.ok) {
    throw std::invalid_argument(s.source_path + ": firmware configuration: " +
                                (b.firmware_error.empty() ? b.error : b.firmware_error));
  }
  fw::FirmwareConfig& c = b.config;
  if (c.mission == fw::MissionKind::Coverage && c.coverage.mode == fw::CoverageMode::Systematic &&
      !s.map) {
    throw std::invalid_argument(s.source_path +
                                ": map: a systematic coverage mission plans on a map, none given");
  }
  if (s.map && map != nullptr) {
    // On a map the world frame is the map frame: goals stay as written; the firmware is told
    // where it starts (the true start unless the scenario says otherwise).
    *map = fw::OccupancyGrid(s.map->cells.size());
    if (const fw::Status st = map->assign(s.map->info, s.map->cells.data()); !st) {
      throw std::invalid_argument(s.source_path + ": map: " + st.message());
    }
    c.map = map;
    // The same set-up as the robot target's mission file with a map; the firmware is told the
    // true start unless the scenario says otherwise.
    loader::LocalisationStartSpec start;
    start.global = s.localisation.global;
    start.recovery = s.localisation.recovery;
    start.initial_sigma_xy_m = s.localisation.initial_sigma_xy_m;
    start.initial_sigma_yaw_rad = s.localisation.initial_sigma_yaw_rad;
    start.max_unlocalised_s = s.localisation.max_unlocalised_s;
    const Pose2 p = s.localisation.initial_pose.value_or(s.robot.start);
    loader::configure_for_map(s.robot, start, {p.x, p.y, p.yaw_rad}, c);
    c.localisation.mcl.seed = seed;
    return c;
  }
  // A scenario's goals are in the world frame; the firmware's odometry starts at the start pose.
  if (c.mission == fw::MissionKind::Goto) {
    c.goto_mission.goal = world_to_odom(s.robot.start, s.mission.goal_x_m, s.mission.goal_y_m,
                                        s.mission.goal_yaw_deg * kPi / 180.0);
    for (fw::Pose2& g : c.goto_mission.goals) g = world_to_odom(s.robot.start, g.x, g.y, g.yaw);
  }
  for (fw::Vec2& t : c.waypoints.targets) {
    const fw::Pose2 o = world_to_odom(s.robot.start, t.x(), t.y(), 0.0);
    t = fw::Vec2(o.x, o.y);
  }
  return c;
}

fw::Status declare_slow_tasks(fw::SlowRateGroup& slow, fw::StatusReporter& reporter,
                              fw::EventSink& events) {
  using fw::TaskSpec;
  if (fw::Status s = slow.init(kSlowRateHz, &events); !s) return s;
  // bind<component method>(name, rate [Hz], offset [cycles], budget [ns], component)
  const TaskSpec table[] = {
      TaskSpec::bind<&fw::StatusReporter::run>("status", 1.0, 0, us(2000), &reporter),
  };
  return slow.add_all(table);
}

namespace {
fw::FirmwareConfig checked(fw::FirmwareConfig c, const ConfigTweak& tweak, const Scenario& s) {
  if (tweak) tweak(c);
  if (const fw::Status st = c.validate(); !st) {
    throw std::invalid_argument(s.source_path + ": firmware configuration: " + st.message());
  }
  return c;
}

std::unique_ptr<fw::Firmware> wired(const fw::FirmwareConfig& c, const hal::Clock& clock,
                                    const Scenario& s) {
  auto f = std::make_unique<fw::Firmware>(c, clock);
  if (const fw::Status st = f->init_status(); !st) {
    throw std::invalid_argument(s.source_path + ": firmware set-up: " + st.message());
  }
  if (const fw::Status st = f->declare_tasks(); !st) {
    throw std::invalid_argument(s.source_path + ": task table: " + st.message());
  }
  return f;
}
}  // namespace

SimTopology::SimTopology(const Scenario& s, std::uint64_t seed, const ConfigTweak& tweak)
    : scenario(s),
      world(s),
      camera_renderer(s, seed),
      lidar(s.robot.lidar, seed),
      encoders(s.odometry, seed),
      gyro(s.robot.imu, seed),
      drives(world.wheel_count()),
      devices{clock, drives, camera, scanner, imu, &cloud},
      config(checked(firmware_config(s, &static_map, seed), tweak, s)),
      firmware(wired(config, clock, s)),
      app(devices, firmware->controller),
      reporter(firmware->status, console),
      slow_divisor(fw::TaskTable::divisor_for(config.rate_hz, kSlowRateHz)) {
  if (config.mapping.terrain) {
    Lidar3dConfig lc;
    lc.sensor = s.robot.lidar3d;
    if (const fw::Status st = lc.validate(); !st) {
      throw std::invalid_argument(s.source_path + ": lidar3d: " + st.message());
    }
    lidar3d = std::make_unique<Lidar3dSim>(lc, seed);
  }
  if (const fw::Status st = declare_slow_tasks(slow, reporter, slow_events); !st) {
    throw std::invalid_argument(s.source_path + ": slow rate group: " + st.message());
  }
}

}  // namespace carril::sim
