#include "firmware/estimation/AliasSearch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "firmware/estimation/BeamsThroughWalls.hpp"
#include "firmware/estimation/ScanBeams.hpp"

namespace carril::fw {

Status AliasSearchConfig::validate() const {
  Checks c("localisation.alias");
  return c.range("stride_m", stride_m, 1e-3, 10.0, "m")
      .range("headings", headings, 1, 16, "headings")
      .range("min_separation_m", min_separation_m, 0.0, 1e3, "m")
      .range("clearance_m", clearance_m, 0.0, 10.0, "m")
      .range("margin", margin, 0.0, 100.0, "log(1/m) per beam")
      .range("max_beams", max_beams, 1, hal::kMaxScanBeams, "beams")
      .range("coarse_beams", coarse_beams, 1, hal::kMaxScanBeams, "beams")
      .range("max_range_m", max_range_m, 0.01, 1e3, "m")
      .range("max_through_fraction", max_through_fraction, 0.0, 1.0, "")
      .range("through_margin_m", through_margin_m, 0.0, 10.0, "m")
      .result();
}

AliasSearch::AliasSearch(const AliasSearchConfig& cfg, const LikelihoodField& field,
                         const OccupancyGrid& map)
    : cfg_(cfg), status_(cfg.validate()), field_(field), map_(map) {
  if (!status_) return;
  if (!field_.ok() || map.empty()) {
    status_ = Status::error("localisation.alias: no map to search");
    return;
  }
  if (map.nx() > 65535 || map.ny() > 65535) {
    status_ =
        Status::error("localisation.alias: map of %d x %d cells, expected at most 65535 a side",
                      map.nx(), map.ny());
    return;
  }
  inv_res_ = 1.0 / field_.resolution();
  gx0_ = 1.0 - field_.origin_x() * inv_res_;
  gy0_ = 1.0 - field_.origin_y() * inv_res_;
  const int step = std::max(1, int(std::lround(cfg_.stride_m * inv_res_)));
  const auto usable = [&](int i, int j) {
    return map.is_free(i, j) && field_.distance(i, j) >= cfg_.clearance_m;
  };
  long n = 0;
  for (int j = 0; j < map.ny(); j += step) {
    for (int i = 0; i < map.nx(); i += step) n += usable(i, j) ? 1 : 0;
  }
  cand_ = std::make_unique<std::uint16_t[]>(std::size_t(2 * std::max(n, 1L)));
  for (int j = 0; j < map.ny(); j += step) {
    for (int i = 0; i < map.nx(); i += step) {
      if (!usable(i, j)) continue;
      cand_[std::size_t(2 * n_cand_)] = std::uint16_t(i);
      cand_[std::size_t(2 * n_cand_ + 1)] = std::uint16_t(j);
      ++n_cand_;
    }
  }
  bx_ = std::make_unique<float[]>(std::size_t(cfg_.max_beams));
  by_ = std::make_unique<float[]>(std::size_t(cfg_.max_beams));
  cbx_ = std::make_unique<float[]>(std::size_t(cfg_.max_beams));
  cby_ = std::make_unique<float[]>(std::size_t(cfg_.max_beams));
}

Pose2 AliasSearch::world(float gx, float gy, double yaw) const {
  return {(double(gx) - gx0_) / inv_res_, (double(gy) - gy0_) / inv_res_, wrap_angle(yaw)};
}

bool AliasSearch::begin(const hal::LaserScan& scan, const Pose2& pose, const Pose2& laser_mount) {
  phase_ = Phase::Idle;
  if (!status_) return false;
  const BeamEndpoints endpoint(laser_mount, inv_res_);
  nb_ = 0;
  for_each_weighed_beam(scan, cfg_.max_range_m, cfg_.max_beams, [&](int i) {
    endpoint(scan, i, bx_[std::size_t(nb_)], by_[std::size_t(nb_)]);
    ++nb_;
  });
  if (nb_ == 0) return false;
  ncb_ = std::min(nb_, cfg_.coarse_beams);
  for (int k = 0; k < ncb_; ++k) {
    const auto b = std::size_t((2L * k + 1) * nb_ / (2L * ncb_));
    cbx_[std::size_t(k)] = bx_[b];
    cby_[std::size_t(k)] = by_[b];
  }
  pose_ = pose;
  if (cfg_.max_through_fraction < 1.0) {
    scan_ = scan;
    mount_ = laser_mount;
  }
  pgx_ = float(pose.x * inv_res_ + gx0_);
  pgy_ = float(pose.y * inv_res_ + gy0_);
  heading_ = 0;
  const double sep = cfg_.min_separation_m * inv_res_;
  min_sep2_ = float(sep * sep);
  n_kept_ = 0;
  cursor_ = 0;
  phase_ = Phase::Scan;
  return true;
}

double AliasSearch::heading_yaw(int k) const {
  return wrap_angle(pose_.yaw + 2.0 * kPi * double(k) / double(cfg_.headings));
}

float AliasSearch::score(float gx, float gy, double yaw) const {
  return field_.sum_log_p(gx, gy, float(std::cos(yaw)), float(std::sin(yaw)), bx_.get(), by_.get(),
                          nb_);
}

bool AliasSearch::passes_walls_check(const Pose2& pose, long& scored) const {
  if (cfg_.max_through_fraction >= 1.0) return true;
  // A walk of 60 returns costs about as much as 32 poses scored (bench_mcl: BM_BeamsThroughWalls
  // 5.1 us, a pose's 60 lookups about 0.16 us).
  scored += 32;
  return beams_through_walls(map_, scan_, pose, mount_, cfg_.max_beams, cfg_.max_range_m,
                             cfg_.through_margin_m)
             .fraction() <= cfg_.max_through_fraction;
}

// The best kKeep, at most one per neighbourhood of min_separation / 2: a mode takes one slot, so
// a second alias elsewhere is not crowded out by the first one's neighbouring cells.
void AliasSearch::keep(float gx, float gy, float s, int heading) {
  const float near2 = 0.25F * min_sep2_;
  for (int k = 0; k < n_kept_; ++k) {
    const float dx = kept_[k].gx - gx, dy = kept_[k].gy - gy;
    if (kept_[k].heading == heading && dx * dx + dy * dy < near2) {
      if (s > kept_[k].score) kept_[k] = {gx, gy, s, heading};
      return;
    }
  }
  if (n_kept_ < kKeep) {
    kept_[n_kept_++] = {gx, gy, s, heading};
    return;
  }
  int worst = 0;
  for (int k = 1; k < kKeep; ++k) {
    if (kept_[k].score < kept_[worst].score) worst = k;
  }
  if (s > kept_[worst].score) kept_[worst] = {gx, gy, s, heading};
}

// Coordinate pattern search in x, y (padded cells) and yaw, the steps halved twice.
Pose2 AliasSearch::refine(const Pose2& p, float& best, long& scored) const {
  float gx = float(p.x * inv_res_ + gx0_), gy = float(p.y * inv_res_ + gy0_);
  double yaw = p.yaw;
  best = score(gx, gy, yaw);
  ++scored;
  float step = 1.0F;
  double dyaw = 0.02;
  for (int level = 0; level < 3; ++level, step *= 0.5F, dyaw *= 0.5) {
    for (int iter = 0; iter < 8; ++iter) {
      const float cand[6][2] = {{step, 0}, {-step, 0}, {0, step}, {0, -step}, {0, 0}, {0, 0}};
      const double yaws[6] = {yaw, yaw, yaw, yaw, yaw + dyaw, yaw - dyaw};
      int arg = -1;
      scored += 6;
      for (int k = 0; k < 6; ++k) {
        const float s = score(gx + cand[k][0], gy + cand[k][1], yaws[k]);
        if (s > best) {
          best = s;
          arg = k;
        }
      }
      if (arg < 0) break;
      gx += cand[arg][0];
      gy += cand[arg][1];
      yaw = yaws[arg];
    }
  }
  return world(gx, gy, yaw);
}

bool AliasSearch::step(long lookups) {
  while (phase_ == Phase::Scan && lookups > 0) {
    const std::uint16_t* c = cand_.get();
    const double yaw = heading_yaw(heading_);
    const float cs = float(std::cos(yaw)), sn = float(std::sin(yaw));
    // At the pose's own heading the positions near it are its own mode; turned, none is.
    const float min_sep2 = heading_ == 0 ? min_sep2_ : -1.0F;
    while (cursor_ < n_cand_ && lookups > 0) {
      // Candidate cell centres in padded grid coordinates: i + 1.5 (the border, the centre).
      const float gx = float(c[2 * cursor_]) + 1.5F, gy = float(c[2 * cursor_ + 1]) + 1.5F;
      ++cursor_;
      const float dx = gx - pgx_, dy = gy - pgy_;
      if (dx * dx + dy * dy < min_sep2) continue;
      keep(gx, gy, field_.sum_log_p(gx, gy, cs, sn, cbx_.get(), cby_.get(), ncb_), heading_);
      lookups -= ncb_;
    }
    if (cursor_ < n_cand_) return true;
    cursor_ = 0;
    if (++heading_ < cfg_.headings) continue;
    cursor_ = -1;  // -1: the pose itself, then the kept aliases
    best_alias_ = -std::numeric_limits<float>::infinity();
    phase_ = Phase::Refine;
  }
  if (phase_ != Phase::Refine) return busy();
  while (phase_ == Phase::Refine && lookups > 0) {
    long scored = 0;
    if (cursor_ < 0) {
      float s = 0.0F;
      result_.pose = refine(pose_, s, scored);
      result_.own_fit = double(s) / double(nb_);
    } else if (cursor_ < n_kept_) {
      float s = 0.0F;
      const Kept& k = kept_[cursor_];
      const Pose2 a = refine(world(k.gx, k.gy, heading_yaw(k.heading)), s, scored);
      // Refinement may climb back towards the pose; such an alias is the pose's own mode.
      const double dx = a.x - result_.pose.x, dy = a.y - result_.pose.y;
      const double sep = cfg_.min_separation_m;
      const bool turned = std::abs(wrap_angle(a.yaw - result_.pose.yaw)) > kPi / 8.0;
      if (s > best_alias_ && (turned || dx * dx + dy * dy >= 0.25 * sep * sep) &&
          passes_walls_check(a, scored)) {
        best_alias_ = s;
        best_alias_pose_ = a;
      }
    }
    lookups -= scored * nb_;
    if (++cursor_ >= n_kept_) {
      result_.alias_fit = double(best_alias_) / double(nb_);
      result_.alias = best_alias_pose_;
      result_.ambiguous = result_.alias_fit >= result_.own_fit - cfg_.margin;
      ++completed_;
      phase_ = Phase::Idle;
    }
  }
  return busy();
}

}  // namespace carril::fw
