#pragma once
// Component: where the robot is in the map frame. Without a map it passes odometry through (the
// map frame is then the odometry frame). On a known map it runs Monte Carlo localisation
// (firmware/estimation/MonteCarloLocalizer) on the 2D scans, spread over ticks with a particle
// budget per tick, and publishes every tick the odometry pose carried into the map frame by the
// newest correction (map <- odom, as AMCL's transform): smooth between scans, corrected at each
// completed update. The missions and the costmap read this pose.
//
// Localised means a tight spread and scans that fit the map at the published pose. A scan that
// stops fitting (a kidnap) makes it lost at once, before the costmap marks that scan; with
// recovery on the particles are then spread over the whole map again. Regained only after the
// scans have fitted for a while (see regain_turn_rad), which counts as a relocalisation: the pose
// may have jumped, and the costmap and the mission are told through OdometryMsg.
#include <cstdint>

#include <memory>
#include "firmware/core/SampleReader.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/SensorFrame.hpp"

#include "firmware/estimation/AliasSearch.hpp"
#include "firmware/estimation/BeamsThroughWalls.hpp"
#include "firmware/estimation/MonteCarloLocalizer.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "firmware/msg/OdometryMsg.hpp"

namespace carril::fw {

struct LocalisationConfig {
  bool enabled = false;  // a static map is given: localise on it
  Pose2 initial_pose;    // the robot's start as the operator gives it, map frame [m, m, rad]
  bool global = false;   // no start given: particles spread over the whole free space
  double initial_sigma_xy_m = 0.5;      // spread round initial_pose [m]
  double initial_sigma_yaw_rad = 0.35;  // [rad]
  MclConfig mcl;
  int particles_per_tick = 500;  // the filter's work per tick (~0.1 ms) [particles]
  // Localised while the estimate's standard deviation stays within these (and lost beyond twice
  // them): the missions drive only then [m], [rad].
  double localised_sigma_xy_m = 0.15;
  double localised_sigma_yaw_rad = 0.1;
  // Lost too as soon as a scan stops fitting the map at the published pose (a kidnap, a wrong
  // convergence): its per-beam likelihood there has fallen below lost_fit_ratio x its running
  // average while localised. Localised again only with a scan back above regain_fit_ratio x that
  // average (and the spread within bounds). Checked on every scan, before the costmap marks it.
  double lost_fit_ratio = 0.2;
  double regain_fit_ratio = 0.5;
  double fit_average_alpha = 0.02;  // weight of a new scan in that average (while localised)
  // The likelihood scores where beams end, not what they pass: at a wrong pose among alike
  // aisles a scan can score well with many returns beyond the map's walls (BeamsThroughWalls).
  // A scan fits only with at most regain_through_fraction of its returns through a wall to
  // regain (and to prove a global start, whose likelihood has nothing to be compared with),
  // and at most lost_through_fraction to stay localised. Searching, a tight cloud whose scan
  // crosses more than lost_through_fraction is a wrong convergence: spread again, as on a
  // loss. Each return is walked from through_margin_m past the scanner to through_margin_m
  // short of its end (the pose's error where a beam grazes a wall) [-], [-], [m].
  double regain_through_fraction = 0.1;
  double lost_through_fraction = 0.3;
  double through_margin_m = 0.3;
  // Localised again only once the scans have fitted, in a row, while the robot turned
  // regain_turn_rad (a 180 deg lidar has then seen all round), or for regain_scans scans if it
  // cannot turn, and the spread is tight: in a house of similar rooms one view often fits a
  // wrong room too, the next views rarely do [rad], [scans].
  double regain_turn_rad = 3.14159265358979;
  int regain_scans = 200;
  // Lost by the fit with recovery on (mcl.alpha_slow > 0): the particles are spread over the
  // whole free space again (a kidnapped robot may be anywhere; injection alone finds it slowly,
  // and a tight cloud in the wrong room outvotes the few injected particles).
  bool spread_when_lost = true;
  // While not localised the filter weighs with its search model (mcl.search_*), localised with
  // the tracking one: searching a whole house, a sharp model collapses the spread onto the first
  // room that fits one view; tracking wants it sharp (its accuracy).
  bool search_while_unlocalised = false;
  // Spread over the whole map at the start (global), the first localisation too waits for the
  // scans to fit through regain_turn_rad (or regain_scans): one view often fits a wrong room.
  // While not localised the filter weighs a scan at least this often even if the robot has not
  // moved (held still it would never update), and no more often: the same view weighed at every
  // scan counts one piece of evidence many times and collapses the filter onto a wrong room [s].
  double unlocalised_update_period_s = 0.5;
  // Regaining (or proving a global start), the pose must also be the only one that explains a
  // scan: no pose alias.min_separation_m or more away fits within alias.margin of it
  // (AliasSearch, over the whole map, at the pose's heading and turned by a quarter, a half and
  // three quarters of a turn). Among alike aisles the filter
  // otherwise converges one aisle over as often as on the right one; refused, the robot stays
  // lost and explores until a view tells them apart. Its max_beams and max_range_m are the
  // filter's; an alias must pass the walls check a regain passes (regain_through_fraction,
  // through_margin_m). While a search runs its lookups come out of particles_per_tick.
  // alias_lookups_per_tick bounds the search's work per tick [field lookups]. An alias found is
  // also given to the filter as a hypothesis: alias_hypothesis_fraction of the particles drawn
  // round it (MonteCarloLocalizer::add_hypothesis), so the next views weigh it against the cloud (a
  // cloud converged one aisle over, or turned half round, moves to the right pose instead of
  // waiting for random injection to find it) [-], [m], [rad].
  bool alias_check = true;
  AliasSearchConfig alias;
  int alias_lookups_per_tick = 20000;
  double alias_hypothesis_fraction = 0.3;
  double alias_hypothesis_sigma_xy_m = 0.1;
  double alias_hypothesis_sigma_yaw_rad = 0.05;

  Status validate() const;
  bool operator==(const LocalisationConfig&) const = default;
};

struct LocalisationTelemetry {
  std::uint64_t updates = 0;   // completed measurement updates
  Pose2 pose;                  // the published pose, map frame [m, m, rad]
  double sigma_xy_m = 0.0;     // the estimate's position spread (largest axis) [m]
  double sigma_yaw_rad = 0.0;  // its yaw spread [rad]
  int particles = 0;           // particles in the filter
  bool localised = true;
  std::uint32_t lost = 0;                // times it went from localised to not
  std::uint32_t lost_by_fit = 0;         // of those, the times the scans stopped fitting
  std::uint32_t relocalisations = 0;     // times it was localised again after being lost
  std::uint32_t spreads = 0;             // times the particles were spread afresh on a loss
  std::uint32_t wrong_convergences = 0;  // of those, spreads of a tight cloud a scan contradicted
  // The latest scan's per-beam likelihood at the published pose over its average (1 before
  // the first localisation).
  double fit_ratio = 1.0;
  // The latest scan's returns through the map's walls at the published pose, of those checked.
  double through_fraction = 0.0;
  std::uint32_t alias_searches = 0;    // completed alias searches (alias_check)
  std::uint32_t alias_ambiguous = 0;   // of those, the ones that found an alias: not regained
  std::uint32_t alias_hypotheses = 0;  // aliases given to the filter as hypotheses
  AliasResult alias;                   // the latest search's result
  MclTelemetry mcl;
};

// Pose composition: a then b (b expressed in a's frame).
Pose2 compose(const Pose2& a, const Pose2& b);
// The inverse transform of p.
Pose2 inverse(const Pose2& p);

class Localisation {
 public:
  // map: the static map (non-null when cfg.enabled; must outlive this).
  // lidar_mount: the 2D lidar in the robot frame (ObstacleSensingConfig::mount()) [m, m, rad].
  Localisation(const LocalisationConfig& cfg, const Pose2& lidar_mount, const OccupancyGrid* map,
               const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& odom,
               Topic<OdometryMsg>& pose);

  // Task: one tick of localisation work, then the pose out.
  void run();
  const LocalisationTelemetry& telemetry() const;
  // The filter's set-up (ok without a map).
  Status init_status() const { return mcl_ ? mcl_->status() : Status::ok(); }
  // The correction map <- odom in use.
  const Pose2& map_from_odom() const { return map_from_odom_; }
  // The filter (nullptr without a map).
  const MonteCarloLocalizer* filter() const { return mcl_.get(); }

 private:
  LocalisationConfig cfg_;
  Pose2 lidar_mount_;
  const OccupancyGrid* map_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  Topic<OdometryMsg>& out_;
  Pose2 map_from_odom_;
  std::unique_ptr<MonteCarloLocalizer> mcl_;
  std::unique_ptr<AliasSearch> alias_;      // alias_check's search (nullptr when off)
  bool alias_clear_ = false;                // a search found none since the scans began to fit
  Pose2 alias_odom_;                        // the odometry pose of the search's scan
  bool alias_pending_ = false;              // an alias to give the filter between updates
  SampleReader<hal::LaserScan> scans_;      // weighed by the filter (when it is free)
  SampleReader<hal::LaserScan> fit_scans_;  // checked against the map (every one)
  std::uint64_t seen_updates_ = 0;
  bool localised_ = false;
  bool ever_localised_ = false;
  bool fits_ = true;                 // the latest scans fit the map at the published pose
  int fitting_scans_ = 0;            // scans in a row that fit well enough to regain
  double fitting_turn_rad_ = 0.0;    // the odometry's turn over those scans [rad]
  double last_fit_yaw_ = 0.0;        // odometry yaw at the latest scan checked [rad]
  std::int64_t last_update_ns_ = 0;  // when the latest update began
  double fit_average_ = 0.0;         // running mean log p per beam while localised [log(1/m)]
  double fit_decay_ = 1.0;           // (1 - alpha)^scans averaged: the average's bias correction
  void check_fit(const hal::LaserScan& scan, const Pose2& odom_pose);
  // Whether the pose has been shown to have no alias since the scans began to fit; if not and
  // no search is running, begins one with this scan.
  bool no_alias(const hal::LaserScan& scan, const Pose2& pose, const Pose2& odom_pose);
  void reset_fitting();
  void step_alias_search();
  // The filter's particle budget this tick: particles_per_tick, less the alias search's share
  // while one runs (the task's time stays about the same).
  int particle_budget() const;
  // The estimate's spread is within the localised bounds (twice them while localised).
  bool tight() const;
  void decide();
  void take_estimate();
  // The telemetry's spread from the filter's covariance.
  void take_spread();
  mutable LocalisationTelemetry tel_;
};

}  // namespace carril::fw
