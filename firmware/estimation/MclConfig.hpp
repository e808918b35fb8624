#pragma once
// Configuration of Monte Carlo localisation (MonteCarloLocalizer). Names and defaults follow
// AMCL's parameters where they mean the same thing.
#include <cstdint>

#include "firmware/core/Status.hpp"
#include "firmware/estimation/LikelihoodField.hpp"
#include "firmware/estimation/OdometryMotionModel.hpp"

namespace carril::fw {

struct MclConfig {
  int max_particles = 5000;  // storage, and the count of a fresh spread (set_pose, set_global)
  int min_particles = 500;   // KLD-sampling never goes below this
  // Odometry motion model noise (OdometryMotionModel.hpp).
  double alpha1 = 0.2;  // rotation from rotation [rad^2/rad^2]
  double alpha2 = 0.2;  // rotation from translation [rad^2/m^2]
  double alpha3 = 0.2;  // translation from translation [m^2/m^2]
  double alpha4 = 0.2;  // translation from rotation [m^2/rad^2]
  // Likelihood-field sensor model (LikelihoodField.hpp).
  double z_hit = 0.95;                 // weight of the Gaussian hit term
  double z_rand = 0.05;                // weight of the uniform random term
  double sigma_hit_m = 0.2;            // spread of the hit term [m]
  int max_beams = 60;                  // beams weighed per scan, evenly spaced among valid ones
  double laser_max_range_m = 12.0;     // beams at or beyond are skipped; z_max of z_rand [m]
  double likelihood_max_dist_m = 2.0;  // distance to obstacles is clamped here [m]
  bool surface_distance = false;       // LikelihoodFieldConfig::surface_distance
  // Beam skipping (AMCL's do_beamskip, judged at one pose): while tracking, a valid beam whose
  // endpoint, seen from the predicted pose (the estimate moved on by the odometry), lies farther
  // than beam_skip_distance_m plus three standard deviations of the estimate's yaw times the
  // range from every occupied cell is taken to have hit something the map does not show (a box,
  // a person) and is not weighed. Such returns otherwise pull the estimate toward poses that put
  // them on a wall. When more than beam_skip_max_fraction of the valid beams would go, the
  // prediction is suspect (a kidnap, a wrong start) and every beam is weighed. 0 = off.
  double beam_skip_distance_m = 0.3;    // [m]
  double beam_skip_max_fraction = 0.3;  // [-]
  // The joint log-likelihood of a scan is the sum over its n beams times
  // 1 / (1 + (n - 1) beam_correlation): beams whose errors are correlated (the same wall, the
  // same map error) count as fewer independent ones. 0 = independent beams (plain sum).
  double beam_correlation = 0.2;
  // A second sensor model for searching the whole map (set_search: global localisation, a lost
  // robot): its hit spread [m] (0: none, the search uses sigma_hit_m) and beam correlation. A
  // sharp tracking model collapses a sparse spread onto the first room that fits one view.
  double search_sigma_hit_m = 0.0;
  double search_beam_correlation = 0.2;
  // KLD-sampling (KldSampling.hpp).
  double kld_err = 0.01;                  // bound on the KL divergence
  double kld_z = 0.99;                    // standard normal quantile z_(1 - delta), as AMCL's
  double bin_xy_m = 0.5;                  // histogram bin along x and y [m]
  double bin_yaw_rad = 0.17453292519943;  // histogram bin along yaw (10 deg) [rad]
  // Augmented MCL (random injection); both 0 turns it off.
  double alpha_slow = 0.001;  // decay rate of the long-term measurement likelihood average
  double alpha_fast = 0.1;    // decay rate of the short-term average
  // When to update and resample.
  double update_min_d_m = 0.2;    // update after this much translation [m]
  double update_min_a_rad = 0.5;  // or this much rotation [rad]
  int resample_interval = 1;      // resample every this many updates
  std::uint64_t seed = 1;         // random stream seed
  // Spreading an update over ticks: particles weighed per step() call (the lighter phases that
  // follow take the same time budget).
  int step_particles = 500;

  Status validate() const;
  LikelihoodFieldConfig field() const;
  OdometryNoise noise() const { return {alpha1, alpha2, alpha3, alpha4}; }
  bool operator==(const MclConfig&) const = default;
};

}  // namespace carril::fw
