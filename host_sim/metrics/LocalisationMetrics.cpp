#include "host_sim/metrics/LocalisationMetrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace carril::sim {

void LocalisationMetrics::add(double t_s, double error_m, double yaw_error_rad) {
  ticks_.push_back({t_s, error_m, std::abs(yaw_error_rad)});
}

void LocalisationMetrics::kidnap(double t_s) {
  kidnaps_.push_back(ticks_.size());
  kidnap_t_s_.push_back(t_s);
}

std::size_t LocalisationMetrics::settled_from(std::size_t begin, std::size_t end) const {
  const double yaw_bound = kConvergedDeg * std::numbers::pi / 180.0;
  std::size_t from = end;
  // Walk back from the end: the settled stretch is the longest suffix within bounds.
  for (std::size_t k = end; k > begin; --k) {
    const Tick& t = ticks_[k - 1];
    if (!(t.error_m <= kConvergedM && t.yaw_error_rad <= yaw_bound)) break;
    from = k - 1;
  }
  return from;
}

LocalisationScore LocalisationMetrics::score() const {
  LocalisationScore s;
  // Segments between kidnaps; each is scored from the moment it settled.
  std::vector<std::size_t> starts{0};
  starts.insert(starts.end(), kidnaps_.begin(), kidnaps_.end());
  double sum_sq = 0.0, sum_sq_yaw = 0.0;
  for (std::size_t seg = 0; seg < starts.size(); ++seg) {
    const std::size_t b = starts[seg];
    const std::size_t e = seg + 1 < starts.size() ? starts[seg + 1] : ticks_.size();
    const std::size_t from = settled_from(b, e);
    const bool settled = from < e;
    if (seg == 0) {
      if (settled) s.time_to_converge_s = ticks_[from].t_s;
    } else {
      s.relocalised_after_s.push_back(
          settled ? std::optional<double>(ticks_[from].t_s - kidnap_t_s_[seg - 1]) : std::nullopt);
    }
    for (std::size_t k = from; k < e; ++k) {
      sum_sq += ticks_[k].error_m * ticks_[k].error_m;
      sum_sq_yaw += ticks_[k].yaw_error_rad * ticks_[k].yaw_error_rad;
      s.max_error_m = std::max(s.max_error_m, ticks_[k].error_m);
      ++s.converged_ticks;
    }
  }
  if (s.converged_ticks > 0) {
    s.rmse_m = std::sqrt(sum_sq / double(s.converged_ticks));
    s.yaw_rmse_deg = std::sqrt(sum_sq_yaw / double(s.converged_ticks)) * 180.0 / std::numbers::pi;
  }
  return s;
}

}  // namespace carril::sim
