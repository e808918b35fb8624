// The phases of one Monte Carlo localisation update (MonteCarloLocalizer.hpp), each resumable:
// weigh (motion + sensor model per particle), normalise (weights, mean), covariance, then, when
// resampling is due, the alias table, the KLD count, the low-variance draw and the injection.
#include <algorithm>
#include <cmath>

#include "firmware/estimation/MonteCarloLocalizer.hpp"

namespace carril::fw {

void MonteCarloLocalizer::weigh(long& units) {
  const long cost = n_beams_ + kWeighExtraUnits;
  const LikelihoodField& field = *weigh_field_;
  const double inv_res = 1.0 / field_.resolution();
  // Padded grid coordinates of a map point: x * inv_res + gx0 (LikelihoodField::log_p_padded).
  const double gx0 = 1.0 - field_.origin_x() * inv_res, gy0 = 1.0 - field_.origin_y() * inv_res;
  const float* bx = beam_x_.get();
  const float* by = beam_y_.get();
  const int nb = n_beams_;
  const double inv_nb = 1.0 / double(nb);
  while (cursor_ < n_ && units > 0) {
    const int i = cursor_;
    Particle& p = cur_[i];
    if (moved_) p = OdometryMotionModel::sample(p, delta_, rng_);
    double sd = 0.0, cd = 0.0;
    fast_sincos(p.yaw, sd, cd);
    const float c = float(cd), s = float(sd);
    const float gx = float(p.x * inv_res + gx0), gy = float(p.y * inv_res + gy0);
    const float ll = field.sum_log_p(gx, gy, c, s, bx, by, nb);
    cos_[i] = c;
    sin_[i] = s;
    const double lw = lw_[i] + double(temper_) * double(ll);
    lw_[i] = lw;
    lw_max_ = std::max(lw_max_, lw);
    fit_[i] = float(double(ll) * inv_nb);
    ++cursor_;
    units -= cost;
  }
}

void MonteCarloLocalizer::begin_sums() {
  cursor_ = 0;
  sum_w_ = sum_w2_ = sum_wx_ = sum_wy_ = sum_wc_ = sum_ws_ = sum_wfit_ = 0.0;
  sum_cov_.setZero();
}

void MonteCarloLocalizer::normalise(long& units) {
  while (cursor_ < n_ && units > 0) {
    const int i = cursor_;
    const double l = lw_[i] - lw_max_;  // <= 0: exp only underflows
    lw_[i] = l;
    const double w = std::exp(l);
    w_[i] = w;
    sum_w_ += w;
    sum_w2_ += w * w;
    sum_wx_ += w * cur_[i].x;
    sum_wy_ += w * cur_[i].y;
    sum_wc_ += w * double(cos_[i]);
    sum_ws_ += w * double(sin_[i]);
    sum_wfit_ += w * double(fit_[i]);
    ++cursor_;
    units -= kNormaliseUnits;
  }
}

void MonteCarloLocalizer::take_mean() {
  // sum_w_ >= 1: the heaviest particle has weight exp(0).
  estimate_.x = sum_wx_ / sum_w_;
  estimate_.y = sum_wy_ / sum_w_;
  estimate_.yaw = std::atan2(sum_ws_, sum_wc_);
  log_norm_ = std::log(sum_w_);
  tel_.n_eff = sum_w_ * sum_w_ / sum_w2_;
}

void MonteCarloLocalizer::update_averages() {
  // The fit of the posterior: the per-beam likelihood, as the exp of the posterior's weighted
  // mean of the per-beam log-likelihood (bounded by the field's log p: no overflow). The book's
  // w_avg (the plain mean over the predicted particles) falls with the prediction's spread and
  // with the injected particles themselves, so injection breeds injection; AMCL stops that
  // spiral by resetting both averages after every injection, which also stalls a recovery.
  const double w_avg = std::exp(sum_wfit_ / sum_w_);
  if (cfg_.alpha_slow <= 0.0) {
    tel_.w_slow = tel_.w_fast = w_avg;
    tel_.inject_probability = 0.0;
    return;
  }
  // Exponential averages from 0, as the book's, divided by 1 - (1 - alpha)^t (Adam's bias
  // correction): early on each is the mean of the updates so far, so the first update (a tight
  // spread that fits unusually well) does not set w_slow for the next 1 / alpha_slow updates.
  ws_raw_ += cfg_.alpha_slow * (w_avg - ws_raw_);
  wf_raw_ += cfg_.alpha_fast * (w_avg - wf_raw_);
  decay_slow_ *= 1.0 - cfg_.alpha_slow;
  decay_fast_ *= 1.0 - cfg_.alpha_fast;
  tel_.w_slow = ws_raw_ / (1.0 - decay_slow_);
  tel_.w_fast = wf_raw_ / (1.0 - decay_fast_);
  tel_.inject_probability = std::max(0.0, 1.0 - tel_.w_fast / tel_.w_slow);
}

void MonteCarloLocalizer::covariance_pass(long& units) {
  const Vec3 m(estimate_.x, estimate_.y, estimate_.yaw);
  while (cursor_ < n_ && units > 0) {
    const int i = cursor_;
    const Vec3 d(cur_[i].x - m.x(), cur_[i].y - m.y(), wrap_angle(cur_[i].yaw - m.z()));
    sum_cov_.noalias() += w_[i] * (d * d.transpose());
    ++cursor_;
    units -= kCovarianceUnits;
  }
}

void MonteCarloLocalizer::take_covariance() {
  cov_ = sum_cov_ / sum_w_;
}

void MonteCarloLocalizer::finish_weighing() {
  take_covariance();
  estimate_odom_ = odom_;
  estimate_has_odom_ = true;
  ++tel_.updates;
  if (++since_resample_ < cfg_.resample_interval) {
    phase_ = Phase::Idle;
    return;
  }
  since_resample_ = 0;
  alias_.begin(w_.get(), n_, sum_w_);
  phase_ = Phase::Alias;
}

bool MonteCarloLocalizer::bin_insert(const Particle& p) {
  // floor(v) as int(v + 2^20) - 2^20: truncation is floor for the positive sum, and the clamp
  // keeps any particle, however far off, in range.
  const auto bin = [](double v) {
    constexpr double kOff = 1048576.0;
    return int(clampd(v, -1e6, 1e6) + kOff) - int(kOff);
  };
  return bins_.insert(bin(p.x * inv_bin_xy_), bin(p.y * inv_bin_xy_),
                      bin((p.yaw + kPi) * inv_bin_yaw_));
}

void MonteCarloLocalizer::begin_count() {
  bins_.clear();
  n_new_ = 0;
  n_inject_ = 0;
  need_ = cfg_.min_particles;
  phase_ = Phase::Count;
}

// Fox's KLD-sampling: i.i.d. draws (a random pose with the injection probability, else a
// particle by weight) until the count reaches the bound for the bins they occupy.
void MonteCarloLocalizer::count(long& units) {
  const double p_inject = tel_.inject_probability;
  while (units > 0) {
    bool fresh = false;
    if (p_inject > 0.0 && rng_.uniform() < p_inject) {
      fresh = bin_insert(random_free_pose());
      ++n_inject_;
    } else {
      fresh = bin_insert(cur_[alias_.draw(rng_)]);
    }
    if (fresh) {
      need_ = kld_particles(bins_.size(), cfg_.kld_err, cfg_.kld_z, cfg_.min_particles,
                            cfg_.max_particles);
    }
    ++n_new_;
    units -= kCountUnits;
    if (n_new_ >= need_ || n_new_ >= cfg_.max_particles) {
      const int n_sys = n_new_ - n_inject_;
      if (n_sys > 0) {
        resampler_.begin(w_.get(), n_, sum_w_, n_sys, rng_.uniform());
        phase_ = Phase::Resample;
      } else {
        cursor_ = 0;
        phase_ = Phase::Inject;
      }
      return;
    }
  }
}

void MonteCarloLocalizer::finish_resampling() {
  std::swap(cur_, next_);
  n_ = n_new_;
  log_norm_ = std::log(double(n_));
  ++tel_.resamples;
  tel_.injected += std::uint64_t(n_inject_);
  tel_.last_injected = n_inject_;
  phase_ = Phase::Idle;
}

}  // namespace carril::fw
