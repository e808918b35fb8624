#include "firmware/estimation/MonteCarloLocalizer.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include "firmware/estimation/ScanBeams.hpp"
#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {

// A map pose of the robot taken when the odometry read from_odom, carried on by the odometry's
// motion since (to to_odom), that motion taken in the robot's frame.
Pose2 carried(const Pose2& pose, const Pose2& from_odom, const Pose2& to_odom) {
  const Vec2 d = to_robot(from_odom, Vec2(to_odom.x, to_odom.y));
  const Vec2 p = to_world(pose, d);
  return {p.x(), p.y(), wrap_angle(pose.yaw + to_odom.yaw - from_odom.yaw)};
}

int clamp_units(long units) {
  return int(std::min(units, long(INT_MAX)));
}

}  // namespace

MonteCarloLocalizer::MonteCarloLocalizer(const MclConfig& cfg, const OccupancyGrid& map)
    : cfg_(cfg), status_(cfg.validate()), motion_(cfg.noise()), rng_(cfg.seed) {
  if (!status_) return;
  if (map.empty()) {
    status_ = Status::error("localisation: the static map is empty");
    return;
  }
  const std::size_t cells = std::size_t(map.nx()) * std::size_t(map.ny());
  for (std::size_t k = 0; k < cells; ++k) n_free_ += map.data()[k] == cost::kFree ? 1U : 0U;
  if (n_free_ == 0) {
    status_ = Status::error("localisation: the static map has no free cell to place particles");
    return;
  }
  field_ = LikelihoodField(cfg.field(), map);
  if (cfg.search_sigma_hit_m > 0.0) {
    LikelihoodFieldConfig f = cfg.field();
    f.sigma_hit_m = cfg.search_sigma_hit_m;
    search_field_ = LikelihoodField(f, map);
  }
  inv_bin_xy_ = 1.0 / cfg.bin_xy_m;
  inv_bin_yaw_ = 1.0 / cfg.bin_yaw_rad;
  free_ = std::make_unique<std::uint32_t[]>(n_free_);
  for (std::size_t k = 0, f = 0; k < cells; ++k) {
    if (map.data()[k] == cost::kFree) free_[f++] = std::uint32_t(k);
  }
  // Validated to 1 .. 1e6; the clamp tells the compiler too (GCC 12 warns about n * 24 bytes).
  const auto n = std::size_t(std::clamp(cfg.max_particles, 1, 1000000));
  buf_a_ = std::make_unique<Particle[]>(n);
  buf_b_ = std::make_unique<Particle[]>(n);
  cur_ = buf_a_.get();
  next_ = buf_b_.get();
  lw_ = std::make_unique<double[]>(n);
  w_ = std::make_unique<double[]>(n);
  cos_ = std::make_unique<float[]>(n);
  sin_ = std::make_unique<float[]>(n);
  fit_ = std::make_unique<float[]>(n);
  bins_ = BinSet(cfg.max_particles);
  alias_ = AliasTable(cfg.max_particles);
  valid_ = std::make_unique<std::uint16_t[]>(std::size_t(hal::kMaxScanBeams));
  fits_ = std::make_unique<std::uint8_t[]>(std::size_t(hal::kMaxScanBeams));
  beam_x_ = std::make_unique<float[]>(std::size_t(cfg.max_beams));
  beam_y_ = std::make_unique<float[]>(std::size_t(cfg.max_beams));
  set_global();
}

Particle MonteCarloLocalizer::random_free_pose() {
  const std::uint32_t k = free_[rng_.below(n_free_)];
  const int nx = field_.nx();
  const double res = field_.resolution();
  const double i = double(k % std::uint32_t(nx)), j = double(k / std::uint32_t(nx));
  Particle p;
  p.x = field_.origin_x() + (i + rng_.uniform()) * res;
  p.y = field_.origin_y() + (j + rng_.uniform()) * res;
  p.yaw = rng_.uniform(-kPi, kPi);
  return p;
}

void MonteCarloLocalizer::set_pose(const Pose2& mean, double sigma_xy_m, double sigma_yaw_rad) {
  if (!status_) return;
  for (int i = 0; i < cfg_.max_particles; ++i) {
    Particle& p = cur_[i];
    p.x = mean.x + rng_.gaussian(sigma_xy_m);
    p.y = mean.y + rng_.gaussian(sigma_xy_m);
    p.yaw = wrap_angle(mean.yaw + rng_.gaussian(sigma_yaw_rad));
  }
  reset_spread();
}

void MonteCarloLocalizer::set_global() {
  if (!status_) return;
  for (int i = 0; i < cfg_.max_particles; ++i) cur_[i] = random_free_pose();
  reset_spread();
}

bool MonteCarloLocalizer::add_hypothesis(const Pose2& mean, const Pose2& mean_odom,
                                         double sigma_xy_m, double sigma_yaw_rad, double fraction) {
  if (!status_ || busy() || !(fraction > 0.0)) return false;
  // Particles belong to odom_ (the latest update's odometry); before any update, to the next
  // one's, which is mean_odom give or take a scan period.
  const Pose2 m = have_odom_ ? carried(mean, mean_odom, odom_) : mean;
  const int every = std::max(1, int(std::lround(1.0 / std::min(fraction, 1.0))));
  for (int i = 0; i < n_; i += every) {
    Particle& p = cur_[i];
    p.x = m.x + rng_.gaussian(sigma_xy_m);
    p.y = m.y + rng_.gaussian(sigma_xy_m);
    p.yaw = wrap_angle(m.yaw + rng_.gaussian(sigma_yaw_rad));
    lw_[i] = 0.0;  // the heaviest's: log weights are kept relative to the largest
  }
  return true;
}

// A fresh equally weighted set of max_particles in cur_: its mean and covariance, no update
// under way, the next scan weighed whatever the motion, the likelihood averages restarted.
void MonteCarloLocalizer::reset_spread() {
  n_ = cfg_.max_particles;
  for (int i = 0; i < n_; ++i) {
    lw_[i] = 0.0;
    double s = 0.0, c = 0.0;
    fast_sincos(cur_[i].yaw, s, c);
    cos_[i] = float(c);
    sin_[i] = float(s);
    fit_[i] = 0.0F;
  }
  lw_max_ = 0.0;
  begin_sums();
  long units = LONG_MAX;
  normalise(units);
  take_mean();
  cursor_ = 0;
  covariance_pass(units);
  take_covariance();
  phase_ = Phase::Idle;
  have_odom_ = false;
  estimate_has_odom_ = false;
  since_resample_ = 0;
  tel_.w_slow = tel_.w_fast = 0.0;
  ws_raw_ = wf_raw_ = 0.0;
  decay_slow_ = decay_fast_ = 1.0;
  tel_.inject_probability = 0.0;
}

bool MonteCarloLocalizer::begin_update(const hal::LaserScan& scan, const Pose2& odom_pose,
                                       const Pose2& laser_mount) {
  if (!status_) return false;
  if (busy()) {
    ++tel_.dropped_scans;
    return false;
  }
  if (have_odom_ && !force_next_) {
    const double d = std::hypot(odom_pose.x - odom_.x, odom_pose.y - odom_.y);
    const double a = std::abs(wrap_angle(odom_pose.yaw - odom_.yaw));
    if (d < cfg_.update_min_d_m && a < cfg_.update_min_a_rad) return false;
  }
  // Valid beams (ScanBeams.hpp).
  const ValidReturn valid(scan, cfg_.laser_max_range_m);
  const int count = std::min(int(scan.count), hal::kMaxScanBeams);
  int nv = 0;
  for (int i = 0; i < count; ++i) {
    if (valid(scan.ranges_m[std::size_t(i)])) valid_[std::size_t(nv++)] = std::uint16_t(i);
  }
  if (nv == 0) return false;
  nv = skip_unmapped(scan, odom_pose, laser_mount, nv);
  // max_beams of them, evenly spaced, as endpoints in the robot frame [cells].
  n_beams_ = std::min(nv, cfg_.max_beams);
  const BeamEndpoints endpoint(laser_mount, 1.0 / field_.resolution());
  for (int k = 0; k < n_beams_; ++k) {
    const int i = valid_[std::size_t((2L * k + 1) * nv / (2L * n_beams_))];
    endpoint(scan, i, beam_x_[std::size_t(k)], beam_y_[std::size_t(k)]);
  }
  const double rho = search_ ? cfg_.search_beam_correlation : cfg_.beam_correlation;
  temper_ = float(1.0 / (1.0 + double(n_beams_ - 1) * rho));
  weigh_field_ = search_ && search_field_.ok() ? &search_field_ : &field_;
  force_next_ = false;
  moved_ = have_odom_;
  if (moved_) delta_ = motion_.delta(odom_, odom_pose);
  odom_ = odom_pose;
  have_odom_ = true;
  tel_.beams_used = n_beams_;
  lw_max_ = -1e300;
  cursor_ = 0;
  phase_ = Phase::Weigh;
  return true;
}

// Beam skipping (MclConfig::beam_skip_distance_m): drops from valid_[0..nv) the beams whose
// endpoints, from the predicted pose, lie off the map's obstacles; returns the count left. Only
// while tracking an estimate, and not when too many would go. O(nv).
int MonteCarloLocalizer::skip_unmapped(const hal::LaserScan& scan, const Pose2& odom_pose,
                                       const Pose2& laser_mount, int nv) {
  tel_.beams_skipped = 0;
  if (cfg_.beam_skip_distance_m <= 0.0 || search_ || !estimate_has_odom_) return nv;
  const Pose2 pred = map_pose(odom_pose);
  const Vec2 sensor = to_world(pred, Vec2(laser_mount.x, laser_mount.y));
  const double yaw0 = pred.yaw + laser_mount.yaw;
  // A long beam's endpoint swings with the estimate's yaw: the test widens by three standard
  // deviations of it times the range. With the distance alone a small yaw error moved the far
  // endpoints off the walls, the beams that would have corrected it were the ones dropped, and a
  // tracking filter of the unit tests lost its pose.
  const double sd_yaw3 = 3.0 * std::sqrt(std::max(0.0, cov_(2, 2)));
  int kept = 0;
  for (int v = 0; v < nv; ++v) {
    const int i = valid_[std::size_t(v)];
    const double a =
        yaw0 + double(scan.angle_min_rad) + double(i) * double(scan.angle_increment_rad);
    const double r = double(scan.ranges_m[std::size_t(i)]);
    const bool fits =
        field_.distance_at(sensor.x() + r * std::cos(a), sensor.y() + r * std::sin(a)) <=
        cfg_.beam_skip_distance_m + sd_yaw3 * r;
    fits_[std::size_t(v)] = fits ? 1 : 0;
    kept += fits ? 1 : 0;
  }
  if (kept == 0 || double(nv - kept) > cfg_.beam_skip_max_fraction * double(nv)) {
    if (kept < nv) ++tel_.skip_refused;
    return nv;
  }
  int w = 0;
  for (int v = 0; v < nv; ++v) {
    if (fits_[std::size_t(v)] != 0) valid_[std::size_t(w++)] = valid_[std::size_t(v)];
  }
  tel_.beams_skipped = nv - w;
  return w;
}

double MonteCarloLocalizer::scan_fit(const hal::LaserScan& scan, const Pose2& pose,
                                     const Pose2& laser_mount) const {
  if (!status_) return std::nan("");
  // The same valid beams as begin_update's, the same even spacing, without its buffers (an
  // update may be using them).
  const Vec2 sensor = to_world(pose, Vec2(laser_mount.x, laser_mount.y));
  const double yaw0 = pose.yaw + laser_mount.yaw;
  double sum = 0.0;
  const int k = for_each_weighed_beam(scan, cfg_.laser_max_range_m, cfg_.max_beams, [&](int i) {
    const double a =
        yaw0 + double(scan.angle_min_rad) + double(i) * double(scan.angle_increment_rad);
    const double r = double(scan.ranges_m[std::size_t(i)]);
    sum += double(field_.log_p(sensor.x() + r * std::cos(a), sensor.y() + r * std::sin(a)));
  });
  if (k == 0) return std::nan("");
  return sum / double(k);
}

void MonteCarloLocalizer::set_search(bool on) {
  if (on == search_) return;
  search_ = on;
  tel_.w_slow = tel_.w_fast = 0.0;
  ws_raw_ = wf_raw_ = 0.0;
  decay_slow_ = decay_fast_ = 1.0;
  tel_.inject_probability = 0.0;
}

bool MonteCarloLocalizer::update(const hal::LaserScan& scan, const Pose2& odom_pose,
                                 const Pose2& laser_mount) {
  if (!begin_update(scan, odom_pose, laser_mount)) return false;
  while (step(cfg_.max_particles)) {
  }
  return true;
}

bool MonteCarloLocalizer::step(int particle_budget) {
  long units = long(std::max(particle_budget, 1)) * (n_beams_ + kWeighExtraUnits);
  while (units > 0 && phase_ != Phase::Idle) {
    switch (phase_) {
      case Phase::Weigh:
        weigh(units);
        if (cursor_ == n_) {
          begin_sums();
          phase_ = Phase::Normalise;
        }
        break;
      case Phase::Normalise:
        normalise(units);
        if (cursor_ == n_) {
          take_mean();
          update_averages();
          cursor_ = 0;
          phase_ = Phase::Covariance;
        }
        break;
      case Phase::Covariance:
        covariance_pass(units);
        if (cursor_ == n_) finish_weighing();
        break;
      case Phase::Alias:
        units -= kAliasUnits * alias_.build(clamp_units(units / kAliasUnits + 1));
        if (alias_.ready()) begin_count();
        break;
      case Phase::Count:
        count(units);
        break;
      case Phase::Resample: {
        Particle* out = next_;
        const Particle* in = cur_;
        double* lw = lw_.get();
        units -= kResampleUnits * resampler_.run(clamp_units(units / kResampleUnits + 1),
                                                 [out, in, lw](int j, int i) {
                                                   out[j] = in[i];
                                                   lw[j] = 0.0;
                                                 });
        if (resampler_.done()) {
          cursor_ = n_new_ - n_inject_;
          phase_ = Phase::Inject;
        }
        break;
      }
      case Phase::Inject:
        while (cursor_ < n_new_ && units > 0) {
          next_[cursor_] = random_free_pose();
          lw_[cursor_] = 0.0;
          ++cursor_;
          units -= kInjectUnits;
        }
        if (cursor_ == n_new_) finish_resampling();
        break;
      case Phase::Idle:
        break;
    }
  }
  return busy();
}

Pose2 MonteCarloLocalizer::map_pose(const Pose2& odom_now) const {
  if (!estimate_has_odom_) return estimate_;
  return carried(estimate_, estimate_odom_, odom_now);
}

Pose2 MonteCarloLocalizer::map_from_odom() const {
  if (!estimate_has_odom_) return {};
  // T with T * estimate_odom = estimate: rotation by the yaw difference, then the translation
  // that carries the rotated odometry position onto the estimate.
  const double yaw = wrap_angle(estimate_.yaw - estimate_odom_.yaw);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double ox = estimate_odom_.x, oy = estimate_odom_.y;
  return {estimate_.x - (c * ox - s * oy), estimate_.y - (s * ox + c * oy), yaw};
}

double MonteCarloLocalizer::weight(int i) const {
  return std::exp(lw_[i] - log_norm_);
}

}  // namespace carril::fw
