#include "loader/MapMission.hpp"

#include <numbers>

namespace carril::loader {

void configure_for_map(const RobotSpec& robot, const LocalisationStartSpec& start,
                       const fw::Pose2& default_pose, fw::FirmwareConfig& c) {
  // Indoors on a surveyed floor: no terrain layer (nor a 3D lidar to read for it).
  c.mapping.terrain = false;
  fw::LocalisationConfig& l = c.localisation;
  l.enabled = true;
  l.global = start.global;
  l.initial_pose = start.has_initial_pose
                       ? fw::Pose2{start.initial_pose.x_m, start.initial_pose.y_m,
                                   start.initial_pose.yaw_deg * std::numbers::pi / 180.0}
                       : default_pose;
  l.initial_sigma_xy_m = start.initial_sigma_xy_m;
  l.initial_sigma_yaw_rad = start.initial_sigma_yaw_rad;
  l.mcl.laser_max_range_m = robot.lidar.range_max_m;
  // The robot file's model of its lidar and odometry (the firmware's defaults where it is silent).
  const LocalisationModelSpec& m = robot.localisation;
  l.mcl.sigma_hit_m = m.sigma_hit_m.value_or(l.mcl.sigma_hit_m);
  l.mcl.beam_correlation = m.beam_correlation.value_or(l.mcl.beam_correlation);
  l.mcl.alpha1 = m.alpha1.value_or(l.mcl.alpha1);
  l.mcl.alpha2 = m.alpha2.value_or(l.mcl.alpha2);
  l.mcl.alpha3 = m.alpha3.value_or(l.mcl.alpha3);
  l.mcl.alpha4 = m.alpha4.value_or(l.mcl.alpha4);
  l.mcl.surface_distance = m.surface_distance.value_or(l.mcl.surface_distance);
  // Random injection can trade a right estimate for a wrong one in a symmetric building: only
  // when asked (a robot that may be carried elsewhere).
  if (!start.recovery) l.mcl.alpha_fast = l.mcl.alpha_slow = 0.0;
  // A robot that cannot find itself (a global start among alike aisles, a map that no longer
  // shows the floor) gives up with not_localised rather than wait for ever; by default after a
  // minute: the slowest convergence in the shipped scenarios is 23 s (the warehouse, told
  // nothing).
  c.runner.max_unlocalised_s = start.max_unlocalised_s;
  if (start.global || start.recovery) {
    // A robot that may have to find itself with nothing to go by (told nothing, or carried
    // elsewhere): the filter searches the whole map with its wide model while lost, and the robot
    // looks round meanwhile (a turn in place, only with room to turn, shows a 180 deg lidar the
    // whole room). Told where it starts, it waits still. 1 rad/s: a whole turn in 6.3 s, so the
    // filter sees more of the building in its minute; at 0.3 rad/s (21 s a turn) fewer seeds
    // relocalised and more converged wrong first (docs/robustness.md, stop 38).
    l.search_while_unlocalised = true;
    l.mcl.search_sigma_hit_m = m.search_sigma_hit_m.value_or(l.mcl.search_sigma_hit_m);
    l.mcl.search_beam_correlation =
        m.search_beam_correlation.value_or(l.mcl.search_beam_correlation);
    c.runner.lost_turn_radps = 1.0;
    // Still lost after a whole turn (a view that fits several alike places), it drives 2 m legs
    // toward open space at a walking pace and looks round again.
    c.runner.lost_explore.speed_mps = 0.2;
  }
}

}  // namespace carril::loader
