#include "host_sim/metrics/ReferencePath.hpp"

#include <algorithm>
#include <cmath>

#include "host_sim/scenario/HypotScreen.hpp"

namespace carril::sim {
namespace {

constexpr double kDuplicateM = 1e-3;  // consecutive points closer than this are one point
constexpr double kClosedM = 0.01;     // last point this close to the first: a loop
// The segment screen's domain and slack: with coordinates below 1e6 m, every rounding in a
// projection, a midpoint or a half length is below 1e-9 m, a thousandth of the slack.
constexpr double kScreenRangeM = 1e6;
constexpr double kScreenSlackM = 1e-6;

bool in_screen_range(Vec2 p) {
  return std::abs(p.x) <= kScreenRangeM && std::abs(p.y) <= kScreenRangeM;
}

double dist(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

}  // namespace

ReferencePath::ReferencePath(const Scenario& scenario) {
  for (const LineSpec& line : scenario.lines) {
    if (!(line.color == scenario.mission.line_color)) continue;
    for (const Vec2& p : line.points) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
      if (!pts_.empty() && dist(pts_.back(), p) < kDuplicateM) continue;
      pts_.push_back(p);
    }
  }
  if (pts_.size() < 2) {
    pts_.clear();
    return;
  }
  if (pts_.size() >= 3 && dist(pts_.back(), pts_.front()) < kClosedM) {
    closed_ = true;
    // Make the loop exact so that at(L) == at(0) and the wrap is seamless.
    if (dist(pts_.back(), pts_.front()) < kDuplicateM) {
      pts_.back() = pts_.front();
    } else {
      pts_.push_back(pts_.front());
    }
  }
  cum_.reserve(pts_.size());
  cum_.push_back(0.0);
  for (std::size_t i = 1; i < pts_.size(); ++i)
    cum_.push_back(cum_.back() + dist(pts_[i - 1], pts_[i]));
  screen_ = std::all_of(pts_.begin(), pts_.end(), in_screen_range);
  for (std::size_t i = 0; i + 1 < pts_.size(); ++i) {
    const Vec2 a = pts_[i], b = pts_[i + 1];
    mid_.push_back({0.5 * (a.x + b.x), 0.5 * (a.y + b.y)});
    half_.push_back(0.5 * dist(a, b));
  }
}

PathPoint ReferencePath::nearest(Vec2 q) const {
  if (empty()) return PathPoint{0.0, 0.0, q};
  // The first minimum over the start point, then the segments in order: the earliest segment
  // wins a tie, and the start point (index -1) wins a tie with segment 0's start. The hint is
  // tried first and the rest screened against the best so far, so ties are settled by index.
  PathPoint best{0.0, 0.0, pts_.front()};
  best.dist_m = dist(q, pts_.front());
  std::ptrdiff_t best_i = -1;
  const bool screen = screen_ && in_screen_range(q);
  const auto consider = [&](std::size_t i) {
    if (screen) {
      // Every point of the segment is at least |q - mid| - half from q: one farther than the
      // best (the projection's rounding and the slack aside) cannot beat it, nor tie.
      const double mx = q.x - mid_[i].x, my = q.y - mid_[i].y;
      const double reach = best.dist_m + half_[i] + kScreenSlackM;
      if (mx * mx + my * my > reach * reach * (1.0 + 1e-12)) return;
    }
    const Vec2 a = pts_[i], b = pts_[i + 1];
    const double seg = cum_[i + 1] - cum_[i];
    if (!(seg > 0.0)) return;
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double t = std::clamp(((q.x - a.x) * dx + (q.y - a.y) * dy) / (seg * seg), 0.0, 1.0);
    const Vec2 p{a.x + t * dx, a.y + t * dy};
    if (!hypot_may_be_below_or_at(q.x - p.x, q.y - p.y, best.dist_m)) return;
    const double d = dist(q, p);
    if (d < best.dist_m || (d == best.dist_m && std::ptrdiff_t(i) < best_i)) {
      best = PathPoint{cum_[i] + t * seg, d, p};
      best_i = std::ptrdiff_t(i);
    }
  };
  const std::size_t segments = pts_.size() - 1;
  if (hint_ < segments) consider(hint_);
  for (std::size_t i = 0; i < segments; ++i) {
    if (i != hint_) consider(i);
  }
  if (best_i >= 0) hint_ = std::size_t(best_i);
  if (closed_ && best.s_m >= length_m()) best.s_m -= length_m();
  return best;
}

PathPoint ReferencePath::nearest_in(Vec2 q, double s_from, double s_to) const {
  if (empty()) return PathPoint{0.0, 0.0, q};
  const double len = length_m();
  if (!std::isfinite(s_from) || !std::isfinite(s_to)) return nearest(q);

  // Searches arc lengths [a, b] (both within [0, len]); keeps the first minimum, so ties favour
  // the smaller arc length (staying put rather than jumping ahead).
  auto search = [&](double a, double b, PathPoint& best, bool& found) {
    // First segment whose end reaches a.
    std::size_t i =
        static_cast<std::size_t>(std::lower_bound(cum_.begin(), cum_.end(), a) - cum_.begin());
    if (i > 0) --i;
    for (; i + 1 < pts_.size() && cum_[i] <= b; ++i) {
      const double seg = cum_[i + 1] - cum_[i];
      if (!(seg > 0.0)) continue;
      const Vec2 pa = pts_[i], pb = pts_[i + 1];
      const double dx = pb.x - pa.x, dy = pb.y - pa.y;
      const double t_lo = std::clamp((a - cum_[i]) / seg, 0.0, 1.0);
      const double t_hi = std::clamp((b - cum_[i]) / seg, 0.0, 1.0);
      if (t_lo > t_hi) continue;
      const double t =
          std::clamp(((q.x - pa.x) * dx + (q.y - pa.y) * dy) / (seg * seg), t_lo, t_hi);
      const Vec2 p{pa.x + t * dx, pa.y + t * dy};
      if (found && !hypot_may_be_below_or_at(q.x - p.x, q.y - p.y, best.dist_m)) continue;
      const double d = dist(q, p);
      if (!found || d < best.dist_m) {
        best = PathPoint{cum_[i] + t * seg, d, p};
        found = true;
      }
    }
  };

  PathPoint best;
  bool found = false;
  if (closed_) {
    const double span = std::clamp(s_to - s_from, 0.0, len);
    double a = std::fmod(s_from, len);
    if (a < 0.0) a += len;
    if (a + span <= len) {
      search(a, a + span, best, found);
    } else {
      search(a, len, best, found);
      search(0.0, a + span - len, best, found);
    }
    if (found && best.s_m >= len) best.s_m -= len;
  } else {
    const double a = std::clamp(s_from, 0.0, len);
    const double b = std::clamp(s_to, a, len);
    search(a, b, best, found);
  }
  if (!found) {
    const Vec2 p = at(s_from);
    return PathPoint{
        closed_ ? std::fmod(std::fmod(s_from, len) + len, len) : std::clamp(s_from, 0.0, len),
        dist(q, p), p};
  }
  return best;
}

Vec2 ReferencePath::at(double s) const {
  if (pts_.empty()) return Vec2{};
  if (empty()) return pts_.front();
  const double len = length_m();
  if (!std::isfinite(s)) s = 0.0;
  if (closed_) {
    s = std::fmod(s, len);
    if (s < 0.0) s += len;
  } else {
    s = std::clamp(s, 0.0, len);
  }
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(cum_.begin(), cum_.end(), s) - cum_.begin());
  if (i == 0) i = 1;
  if (i >= pts_.size()) return pts_.back();
  const double seg = cum_[i] - cum_[i - 1];
  const double t = seg > 0.0 ? (s - cum_[i - 1]) / seg : 0.0;
  const Vec2 a = pts_[i - 1], b = pts_[i];
  return Vec2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

}  // namespace carril::sim
