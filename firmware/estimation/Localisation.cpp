#include "firmware/estimation/Localisation.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.yaw + b.yaw)};
}

Pose2 inverse(const Pose2& p) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), wrap_angle(-p.yaw)};
}

Status LocalisationConfig::validate() const {
  Checks c("localisation");
  if (!enabled) return c.result();
  return c.range("initial_pose.x", initial_pose.x, -1e4, 1e4, "m")
      .range("initial_pose.y", initial_pose.y, -1e4, 1e4, "m")
      .range("initial_pose.yaw", initial_pose.yaw, -2.0 * kPi, 2.0 * kPi, "rad")
      .range("initial_sigma_xy_m", initial_sigma_xy_m, 0.0, 100.0, "m")
      .range("initial_sigma_yaw_rad", initial_sigma_yaw_rad, 0.0, 2.0 * kPi, "rad")
      .range("particles_per_tick", double(particles_per_tick), 10.0, 1e6, "particles")
      .range("localised_sigma_xy_m", localised_sigma_xy_m, 0.01, 10.0, "m")
      .range("localised_sigma_yaw_rad", localised_sigma_yaw_rad, 0.01, kPi, "rad")
      .range("lost_fit_ratio", lost_fit_ratio, 0.0, 1.0, "")
      .range("regain_fit_ratio", regain_fit_ratio, lost_fit_ratio, 1.0, "")
      .range("fit_average_alpha", fit_average_alpha, 1e-4, 1.0, "")
      .range("regain_through_fraction", regain_through_fraction, 0.0, 1.0, "")
      .range("lost_through_fraction", lost_through_fraction, regain_through_fraction, 1.0, "")
      .range("through_margin_m", through_margin_m, 0.0, 10.0, "m")
      .range("regain_scans", double(regain_scans), 1.0, 10000.0, "scans")
      .range("regain_turn_rad", regain_turn_rad, 0.0, 100.0, "rad")
      .range("unlocalised_update_period_s", unlocalised_update_period_s, 0.0, 60.0, "s")
      .range("alias_lookups_per_tick", double(alias_lookups_per_tick), 100.0, 1e9, "lookups")
      .range("alias_hypothesis_fraction", alias_hypothesis_fraction, 0.0, 1.0, "")
      .range("alias_hypothesis_sigma_xy_m", alias_hypothesis_sigma_xy_m, 0.0, 10.0, "m")
      .range("alias_hypothesis_sigma_yaw_rad", alias_hypothesis_sigma_yaw_rad, 0.0, kPi, "rad")
      .nested(alias_check ? alias.validate() : Status())
      .nested(mcl.validate())
      .result();
}

Localisation::Localisation(const LocalisationConfig& cfg, const Pose2& lidar_mount,
                           const OccupancyGrid* map, const Topic<SensorFrame>& frame,
                           const Topic<OdometryMsg>& odom, Topic<OdometryMsg>& pose)
    : cfg_(cfg), lidar_mount_(lidar_mount), map_(map), frame_(frame), odom_(odom), out_(pose) {
  if (!cfg_.enabled || map_ == nullptr) return;
  // The odometry frame starts where the robot does: at the initial pose in the map frame.
  map_from_odom_ = cfg_.initial_pose;
  mcl_ = std::make_unique<MonteCarloLocalizer>(cfg_.mcl, *map_);
  mcl_->set_search(cfg_.search_while_unlocalised);  // not localised yet
  if (cfg_.alias_check && mcl_->status()) {
    AliasSearchConfig ac = cfg_.alias;
    ac.max_beams = cfg_.mcl.max_beams;
    ac.max_range_m = cfg_.mcl.laser_max_range_m;
    ac.max_through_fraction = cfg_.regain_through_fraction;  // what a regain itself must pass
    ac.through_margin_m = cfg_.through_margin_m;
    alias_ = std::make_unique<AliasSearch>(ac, mcl_->field(), *map_);
  }
  if (cfg_.global) {
    mcl_->set_global();
  } else {
    mcl_->set_pose(cfg_.initial_pose, cfg_.initial_sigma_xy_m, cfg_.initial_sigma_yaw_rad);
  }
}

void Localisation::take_estimate() {
  map_from_odom_ = mcl_->map_from_odom();
  take_spread();
  decide();
}

void Localisation::take_spread() {
  const Mat3& c = mcl_->covariance();
  // Largest standard deviation of the 2 x 2 position block (its larger eigenvalue).
  const double a = c(0, 0), b = c(0, 1), d = c(1, 1);
  const double l1 = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  tel_.sigma_xy_m = std::sqrt(std::max(0.0, l1));
  tel_.sigma_yaw_rad = std::sqrt(std::max(0.0, c(2, 2)));
}

// A tight cloud in the wrong place stays tight until injected particles have widened it, many
// updates after a kidnap: the scan's fit at the published pose tells it at the first scan, before
// the costmap marks that scan and before the missions act on the wrong pose.
void Localisation::check_fit(const hal::LaserScan& scan, const Pose2& odom_pose) {
  const Pose2 pose = compose(map_from_odom_, odom_pose);
  const double fit = mcl_->scan_fit(scan, pose, lidar_mount_);
  if (std::isnan(fit) || seen_updates_ == 0) return;  // no beam, or no estimate yet
  tel_.through_fraction = beams_through_walls(*map_, scan, pose, lidar_mount_, cfg_.mcl.max_beams,
                                              cfg_.mcl.laser_max_range_m, cfg_.through_margin_m)
                              .fraction();
  // Told where it starts, the first convergence needs no proof; spread over the map it does.
  const bool proven = ever_localised_ || cfg_.global;
  if (fit_decay_ >= 1.0) {
    tel_.fit_ratio = 1.0;  // no average yet: nothing to compare with
  } else {
    const double average = fit_average_ / (1.0 - fit_decay_);
    tel_.fit_ratio = std::exp(std::min(fit - average, 0.0));
  }
  const double turn = std::abs(wrap_angle(odom_pose.yaw - last_fit_yaw_));
  last_fit_yaw_ = odom_pose.yaw;
  const bool was_localised = localised_;
  bool wrong = false;  // a tight cloud that the scan contradicts
  if (localised_) {
    fits_ = tel_.fit_ratio >= cfg_.lost_fit_ratio &&
            tel_.through_fraction <= cfg_.lost_through_fraction;
  } else if (tel_.fit_ratio >= cfg_.regain_fit_ratio &&
             tel_.through_fraction <= cfg_.regain_through_fraction) {
    ++fitting_scans_;
    fitting_turn_rad_ += turn;
    fits_ = !proven ||
            ((fitting_scans_ >= cfg_.regain_scans || fitting_turn_rad_ >= cfg_.regain_turn_rad) &&
             no_alias(scan, pose, odom_pose));
  } else {
    reset_fitting();
    fits_ = !proven;
    wrong = proven && tight() && tel_.through_fraction > cfg_.lost_through_fraction;
  }
  decide();
  if (localised_) alias_clear_ = false;  // the next regain proves itself afresh
  if ((was_localised && !localised_) || wrong) {
    reset_fitting();
    // With recovery on (mcl.alpha_slow > 0) the robot may have been carried anywhere; a global
    // start searches the whole map anyway, and a wrong convergence has no other way out.
    const bool recovery = cfg_.mcl.alpha_slow > 0.0 || (wrong && cfg_.global);
    if (cfg_.spread_when_lost && recovery) {
      mcl_->set_global();
      take_spread();  // not tight until an update has drawn the particles together again
      ++tel_.spreads;
      if (wrong) ++tel_.wrong_convergences;
    }
  }
  if (localised_) {
    // Only scans taken while localised set what a fitting scan looks like here.
    fit_average_ += cfg_.fit_average_alpha * (fit - fit_average_);
    fit_decay_ *= 1.0 - cfg_.fit_average_alpha;
  }
}

void Localisation::reset_fitting() {
  fitting_scans_ = 0;
  fitting_turn_rad_ = 0.0;
  alias_clear_ = false;
  alias_pending_ = false;
  if (alias_ != nullptr) alias_->abort();
}

bool Localisation::no_alias(const hal::LaserScan& scan, const Pose2& pose, const Pose2& odom_pose) {
  if (alias_ == nullptr || alias_clear_) return true;
  if (!alias_->busy() && alias_->begin(scan, pose, lidar_mount_)) alias_odom_ = odom_pose;
  return false;
}

int Localisation::particle_budget() const {
  if (alias_ == nullptr || !alias_->busy()) return cfg_.particles_per_tick;
  // The search's lookups come out of the tick's share: a particle costs its beams' lookups and
  // about 24 more (MonteCarloLocalizer's kWeighExtraUnits); the filter keeps a quarter at least.
  const int per_particle = std::max(mcl_->telemetry().beams_used, 1) + 24;
  return std::max(cfg_.particles_per_tick / 4,
                  cfg_.particles_per_tick - cfg_.alias_lookups_per_tick / per_particle);
}

void Localisation::step_alias_search() {
  if (alias_ == nullptr || !alias_->busy()) return;
  if (alias_->step(cfg_.alias_lookups_per_tick)) return;
  tel_.alias = alias_->result();
  ++tel_.alias_searches;
  if (tel_.alias.ambiguous) {
    ++tel_.alias_ambiguous;
    alias_pending_ = cfg_.alias_hypothesis_fraction > 0.0;
  } else {
    alias_clear_ = true;  // the next scan that fits regains
  }
}

bool Localisation::tight() const {
  const double k = localised_ ? 2.0 : 1.0;  // hysteresis: lost only beyond twice the bounds
  return seen_updates_ > 0 && tel_.sigma_xy_m <= k * cfg_.localised_sigma_xy_m &&
         tel_.sigma_yaw_rad <= k * cfg_.localised_sigma_yaw_rad;
}

void Localisation::decide() {
  const bool tight_now = tight();
  const bool ok = tight_now && fits_;
  if (localised_ && !ok) {
    ++tel_.lost;
    if (tight_now) ++tel_.lost_by_fit;
  }
  if (!localised_ && ok && ever_localised_) ++tel_.relocalisations;
  ever_localised_ = ever_localised_ || ok;
  if (cfg_.search_while_unlocalised) mcl_->set_search(!ok);
  localised_ = ok;
}

void Localisation::run() {
  const OdometryMsg& o = odom_.get();
  if (mcl_ != nullptr) {
    const SensorFrame& f = frame_.get();
    if (const hal::LaserScan* scan = fit_scans_.take(f.scan)) check_fit(*scan, o.pose);
    if (alias_pending_ && !mcl_->busy()) {
      alias_pending_ = false;
      if (mcl_->add_hypothesis(tel_.alias.alias, alias_odom_, cfg_.alias_hypothesis_sigma_xy_m,
                               cfg_.alias_hypothesis_sigma_yaw_rad,
                               cfg_.alias_hypothesis_fraction)) {
        ++tel_.alias_hypotheses;
        mcl_->force_next_update();  // weigh it at the next scan
      }
    }
    // A scan that comes while the filter is busy waits: the newest is taken once it is free.
    if (!mcl_->busy() && scans_.take(f.scan) != nullptr) {
      // Held still while lost, the robot would never move enough to update: weigh a scan now and
      // then all the same.
      const auto period_ns = std::int64_t(cfg_.unlocalised_update_period_s * 1e9);
      if (!localised_ && f.now_ns - last_update_ns_ >= period_ns) mcl_->force_next_update();
      if (mcl_->begin_update(*f.scan, o.pose, lidar_mount_)) last_update_ns_ = f.now_ns;
    } else if (mcl_->busy()) {
      (void)mcl_->step(particle_budget());
    }
    step_alias_search();
    if (mcl_->telemetry().updates != seen_updates_) {
      seen_updates_ = mcl_->telemetry().updates;
      take_estimate();
    }
    tel_.updates = seen_updates_;
    tel_.particles = mcl_->particle_count();
  }
  OdometryMsg& m = out_.edit();
  // Without a map the odometry frame is the map frame: passed on unchanged, bit for bit.
  m.pose = mcl_ != nullptr ? compose(map_from_odom_, o.pose) : o.pose;
  m.twist = o.twist;
  m.localised = mcl_ == nullptr || localised_;
  m.relocalisations = tel_.relocalisations;
  out_.publish(frame_.get().now_ns);
  tel_.pose = m.pose;
  tel_.localised = m.localised;
}

const LocalisationTelemetry& Localisation::telemetry() const {
  if (mcl_ != nullptr) tel_.mcl = mcl_->telemetry();
  return tel_;
}

}  // namespace carril::fw
