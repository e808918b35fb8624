#pragma once
// Monte Carlo localisation on the static map (Probabilistic Robotics ch. 8; AMCL's choices where
// the book leaves one open): a particle filter over the robot's pose in the map frame with
//   - the odometry motion model (OdometryMotionModel.hpp),
//   - the likelihood-field sensor model (LikelihoodField.hpp): a scan's log-likelihood is the sum
//     of its beams' log p, tempered by 1 / (1 + (n - 1) beam_correlation) (MclConfig.hpp).
//     AMCL sums cubes of per-beam probabilities, which has no probabilistic reading; a tempered
//     sum of logs is the likelihood of n correlated beams counted as that many independent ones,
//     and keeps several hypotheses alive while the robot moves instead of collapsing on the best
//     of a sparse spread,
//   - low-variance resampling (Resampling.hpp, linear), its count chosen by KLD-sampling
//     (KldSampling.hpp: Fox's sequential bound on i.i.d. draws from an alias table; the set that
//     is kept is then drawn low-variance with that count),
//   - augmented MCL (table 8.3): w_slow and w_fast average how well the scans are explained, and
//     a fraction max(0, 1 - w_fast / w_slow) of the new set is drawn uniformly over free space.
//     What is averaged is the per-beam likelihood of the posterior (the exp of its weighted mean
//     of the per-beam log-likelihood): independent of the beam count, and not dragged down by
//     the injected particles themselves (the book's plain mean is, which feeds more injection; AMCL
//     resets both averages after each injection to stop that, which also stalls a recovery). The
//     averages are bias-corrected (MclPhases.cpp) and never reset but by set_*.
//
// Everything is allocated in the constructor. An update is begun with a scan (begin_update:
// cheap, selects the beams) and carried out by step() calls, each doing a bounded amount of work
// (the motion and weighing of `particle_budget` particles, or the same time of the lighter
// phases), so it can be spread over control ticks; none allocates. Random draws happen in the
// same order whatever the budget: the result does not depend on how the update was spread.
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/estimation/KldSampling.hpp"
#include "firmware/estimation/LikelihoodField.hpp"
#include "firmware/estimation/MclConfig.hpp"
#include "firmware/estimation/MclRandom.hpp"
#include "firmware/estimation/OdometryMotionModel.hpp"
#include "firmware/estimation/Resampling.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// A pose hypothesis in the map frame [m, m, rad].
using Particle = Pose2;

struct MclTelemetry {
  std::uint64_t updates = 0;        // completed updates (motion, weighing, estimate)
  std::uint64_t resamples = 0;      // completed resamplings
  std::uint64_t injected = 0;       // random particles injected, all resamplings
  std::uint64_t dropped_scans = 0;  // scans offered while an update was still running
  int last_injected = 0;            // random particles in the latest resampling
  int beams_used = 0;               // beams weighed in the latest update
  int beams_skipped = 0;            // valid beams of the latest update's scan not weighed
  std::uint64_t skip_refused = 0;   // updates that would have skipped too many beams
  double w_slow = 0.0;              // long-term average per-beam likelihood [1/m]
  double w_fast = 0.0;              // short-term average [1/m]
  double inject_probability = 0.0;  // max(0, 1 - w_fast / w_slow) at the latest update
  double n_eff = 0.0;               // effective particle count of the latest weighing
};

class MonteCarloLocalizer {
 public:
  // Allocates everything and precomputes the likelihood field (init time), then spreads
  // max_particles uniformly over the free cells. status() tells whether cfg and map were usable;
  // if not, every call does nothing.
  MonteCarloLocalizer(const MclConfig& cfg, const OccupancyGrid& map);

  const Status& status() const { return status_; }

  // max_particles drawn around `mean` (map frame) with these standard deviations [m, rad]; the
  // next scan is weighed whatever the motion. Aborts an update under way.
  void set_pose(const Pose2& mean, double sigma_xy_m, double sigma_yaw_rad);
  // max_particles spread uniformly over the free cells and yaws (global localisation).
  void set_global();
  // Another hypothesis (sensor resetting, Lenser and Veloso): about `fraction` of the particles,
  // every round(1 / fraction)-th, drawn anew around `mean`, the robot's map pose when the
  // odometry read `mean_odom` (carried on by the odometry since to the particles' own), with the
  // weight of the heaviest particle: the next scans weigh it against the cloud. Only between
  // updates (false while one is running) [m, rad].
  bool add_hypothesis(const Pose2& mean, const Pose2& mean_odom, double sigma_xy_m,
                      double sigma_yaw_rad, double fraction);

  // Begins an update with a scan taken at odometry pose odom_pose, the lidar at laser_mount in
  // the robot frame. false (nothing to do) while an update is running, when the robot has moved
  // less than update_min_d_m and update_min_a_rad since the last update (the first scan after
  // construction or set_* always updates) or when the scan has no valid beam.
  bool begin_update(const hal::LaserScan& scan, const Pose2& odom_pose, const Pose2& laser_mount);
  // Works on the update for about the time of weighing particle_budget particles; true while
  // the update is still running.
  bool step(int particle_budget);
  bool step() { return step(cfg_.step_particles); }
  bool busy() const { return phase_ != Phase::Idle; }
  // begin_update and steps to the end (tests, tools).
  bool update(const hal::LaserScan& scan, const Pose2& odom_pose, const Pose2& laser_mount);

  // Weighted mean pose (circular mean yaw) in the map frame, for the robot at the odometry pose
  // of the latest completed update.
  const Pose2& estimate() const { return estimate_; }
  // Its covariance (x [m], y [m], yaw [rad]).
  const Mat3& covariance() const { return cov_; }
  // The odometry pose the estimate belongs to.
  const Pose2& estimate_odom() const { return estimate_odom_; }
  // The robot's map pose now: the estimate moved on by the odometry since its update.
  Pose2 map_pose(const Pose2& odom_now) const;
  // The correction map <- odom (AMCL's map -> odom transform): map_pose(o) is this composed
  // with o. Identity until the first completed update.
  Pose2 map_from_odom() const;
  // The next begin_update weighs its scan even if the robot has not moved (a robot held still
  // while it is not localised, so the filter keeps working on what it sees).
  void force_next_update() { force_next_ = true; }
  // Updates begun from now on use the search model (MclConfig::search_*) or the tracking one.
  // The likelihood averages of augmented MCL restart on a change (they are of one model).
  void set_search(bool on);
  bool searching() const { return search_; }

  // How well a scan fits the map with the robot at map pose `pose`: the mean log p per beam
  // [log(1/m)] over the beams an update would weigh (up to max_beams valid ones, evenly spaced).
  // One pose, no particle touched: cheap enough for every scan. NaN without a valid beam.
  double scan_fit(const hal::LaserScan& scan, const Pose2& pose, const Pose2& laser_mount) const;

  int particle_count() const { return n_; }
  const Particle* particles() const { return cur_; }
  // Normalised weight of particle i (after a completed update or set_*).
  double weight(int i) const;
  const MclTelemetry& telemetry() const { return tel_; }
  const LikelihoodField& field() const { return field_; }
  const MclConfig& config() const { return cfg_; }

 private:
  enum class Phase : std::uint8_t {
    Idle,
    Weigh,
    Normalise,
    Covariance,
    Alias,
    Count,
    Resample,
    Inject
  };

  // Work units of one element of each phase, in field lookups (one beam of one particle, the
  // unit of the weighing). bench/MclBench.cpp measures the phases; these keep a step() call
  // within about the time of weighing its particle budget.
  static constexpr long kWeighExtraUnits = 24;  // motion sample (3 Gaussians, 2 sincos), sums
  static constexpr long kNormaliseUnits = 4;    // exp and the weighted sums
  static constexpr long kCovarianceUnits = 2;
  static constexpr long kAliasUnits = 2;
  static constexpr long kCountUnits = 10;  // one draw, its bin, the hash set
  static constexpr long kResampleUnits = 3;
  static constexpr long kInjectUnits = 8;

  // MonteCarloLocalizer.cpp: set-up, the scan, the phase sequence.
  Particle random_free_pose();
  void reset_spread();
  // MclPhases.cpp: the work of each phase. A phase function works until its elements are done or
  // `units` (field lookups' worth of work) is spent, and subtracts what it used.
  void weigh(long& units);
  void begin_sums();
  void normalise(long& units);
  void take_mean();
  void update_averages();
  void covariance_pass(long& units);
  void take_covariance();
  void finish_weighing();
  void begin_count();
  void count(long& units);
  bool bin_insert(const Particle& p);
  void finish_resampling();
  int skip_unmapped(const hal::LaserScan& scan, const Pose2& odom_pose, const Pose2& laser_mount,
                    int nv);

  MclConfig cfg_;
  Status status_;
  LikelihoodField field_;         // the tracking model (scan_fit's too)
  LikelihoodField search_field_;  // the search model's, when its sigma_hit differs
  bool search_ = false;
  const LikelihoodField* weigh_field_ = &field_;  // the model of the update under way
  OdometryMotionModel motion_;
  MclRng rng_;
  BinSet bins_;
  AliasTable alias_;
  LowVarianceResampler resampler_;

  // Particles: two buffers, the current set and the one resampling writes.
  std::unique_ptr<Particle[]> buf_a_, buf_b_;
  Particle* cur_ = nullptr;
  Particle* next_ = nullptr;
  int n_ = 0;
  std::unique_ptr<double[]> lw_;  // log weight of each current particle, max 0
  std::unique_ptr<double[]> w_;   // exp(lw), the resampler's input
  std::unique_ptr<float[]> cos_;  // cos and sin of each particle's yaw, from weighing
  std::unique_ptr<float[]> sin_;
  std::unique_ptr<float[]> fit_;  // mean log p per beam, latest weighing [log(1/m)]
  double log_norm_ = 0.0;         // log of the sum of exp(lw)

  // Free cells of the map, for uniform draws.
  std::unique_ptr<std::uint32_t[]> free_;
  std::uint32_t n_free_ = 0;

  // The update under way.
  Phase phase_ = Phase::Idle;
  int cursor_ = 0;
  std::unique_ptr<std::uint16_t[]> valid_;    // indices of the scan's valid beams
  std::unique_ptr<std::uint8_t[]> fits_;      // beam skipping: per valid beam, 1 = weighed
  std::unique_ptr<float[]> beam_x_, beam_y_;  // beam endpoints in the robot frame [cells]
  int n_beams_ = 0;
  float temper_ = 1.0F;
  bool moved_ = false;
  OdometryDelta delta_;
  Pose2 odom_;               // odometry pose of the update under way (or the last one)
  bool have_odom_ = false;   // false until the first update after construction or set_*
  bool force_next_ = false;  // the next scan updates however little the robot moved
  double lw_max_ = 0.0;
  double sum_w_ = 0.0, sum_w2_ = 0.0, sum_wx_ = 0.0, sum_wy_ = 0.0, sum_wc_ = 0.0, sum_ws_ = 0.0,
         sum_wfit_ = 0.0;
  Mat3 sum_cov_ = Mat3::Zero();
  int since_resample_ = 0;
  double inv_bin_xy_ = 1.0, inv_bin_yaw_ = 1.0;  // 1 / KLD bin sizes [1/m, 1/rad]
  // Augmented MCL's averages before their bias correction, and (1 - alpha)^updates.
  double ws_raw_ = 0.0, wf_raw_ = 0.0, decay_slow_ = 1.0, decay_fast_ = 1.0;
  // Resampling under way.
  int n_new_ = 0, n_inject_ = 0, need_ = 0;

  Pose2 estimate_, estimate_odom_;
  bool estimate_has_odom_ = false;  // false after set_*: the estimate belongs to no odometry
  Mat3 cov_ = Mat3::Zero();
  MclTelemetry tel_;
};

}  // namespace carril::fw
