#include "firmware/estimation/MclConfig.hpp"

#include "hal/Types.hpp"

namespace carril::fw {

LikelihoodFieldConfig MclConfig::field() const {
  LikelihoodFieldConfig f;
  f.z_hit = z_hit;
  f.z_rand = z_rand;
  f.sigma_hit_m = sigma_hit_m;
  f.z_max_m = laser_max_range_m;
  f.max_dist_m = likelihood_max_dist_m;
  f.surface_distance = surface_distance;
  return f;
}

Status MclConfig::validate() const {
  Checks c("localisation");
  c.range("max_particles", max_particles, 1, 1000000, "particles")
      .range("min_particles", min_particles, 1, max_particles, "particles")
      .range("alpha1", alpha1, 0.0, 10.0, "rad^2/rad^2")
      .range("alpha2", alpha2, 0.0, 10.0, "rad^2/m^2")
      .range("alpha3", alpha3, 0.0, 10.0, "m^2/m^2")
      .range("alpha4", alpha4, 0.0, 10.0, "m^2/rad^2")
      .nested(field().validate())
      .range("max_beams", max_beams, 1, hal::kMaxScanBeams, "beams")
      .range("beam_skip_distance_m", beam_skip_distance_m, 0.0, 100.0, "m")
      .range("beam_skip_max_fraction", beam_skip_max_fraction, 0.0, 1.0, "")
      .range("beam_correlation", beam_correlation, 0.0, 1.0, "")
      .range("search_sigma_hit_m", search_sigma_hit_m, 0.0, 10.0, "m")
      .range("search_beam_correlation", search_beam_correlation, 0.0, 1.0, "")
      .range("kld_err", kld_err, 1e-4, 1.0, "")
      .range("kld_z", kld_z, 0.0, 10.0, "")
      .range("bin_xy_m", bin_xy_m, 0.01, 10.0, "m")
      .range("bin_yaw_rad", bin_yaw_rad, 0.001, 2.0 * kPi, "rad")
      .range("alpha_slow", alpha_slow, 0.0, 1.0, "")
      .range("alpha_fast", alpha_fast, 0.0, 1.0, "")
      .range("update_min_d_m", update_min_d_m, 0.0, 100.0, "m")
      .range("update_min_a_rad", update_min_a_rad, 0.0, 2.0 * kPi, "rad")
      .range("resample_interval", resample_interval, 1, 1000, "updates")
      .range("step_particles", step_particles, 1, max_particles, "particles");
  c.fail_if(alpha_slow > 0.0 && !(alpha_fast > alpha_slow), "alpha_fast",
            "must be above alpha_slow (the short-term average must move faster)");
  c.fail_if(alpha_slow == 0.0 && alpha_fast > 0.0, "alpha_slow",
            "is 0 while alpha_fast is not: set both (injection on) or both 0 (off)");
  if (search_sigma_hit_m > 0.0) {
    LikelihoodFieldConfig f = field();
    f.sigma_hit_m = search_sigma_hit_m;
    c.nested(f.validate());
  }
  return c.result();
}

}  // namespace carril::fw
