#include "host_sim/sensors/RayCaster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace carril::sim {

namespace {
// Bounding boxes grow by this much plus a relative part, far above float rounding (~1e-7
// relative) so the culling tests, done in float, never drop a fixture Box2D would hit [m].
constexpr float kPad = 0.01F;
constexpr float kRelPad = 1e-5F;
constexpr int kMaxCells = 512;  // per grid axis
}  // namespace

void RayCaster::prepare(const b2World& world, const b2Body* skip) {
  fresh_.clear();
  movers_.clear();
  // b2World::RayCast sees the broad-phase proxies: every fixture child of the enabled bodies
  // (sensors included).
  for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext()) {
    if (b == skip || !b->IsEnabled()) continue;
    std::vector<Candidate>& into = b->GetType() == b2_staticBody ? fresh_ : movers_;
    for (const b2Fixture* f = b->GetFixtureList(); f != nullptr; f = f->GetNext()) {
      for (std::int32_t k = 0; k < f->GetShape()->GetChildCount(); ++k) {
        // The broad phase's own box of the child (its fat box, which the tree culls by, holds
        // it): kept up to date by Box2D at each step and SetTransform.
        const b2AABB& box = f->GetAABB(k);
        const float big = std::max({std::abs(box.lowerBound.x), std::abs(box.lowerBound.y),
                                    std::abs(box.upperBound.x), std::abs(box.upperBound.y)});
        const float pad = kPad + kRelPad * big;
        into.push_back({f, k, 0.5F * (box.lowerBound.x + box.upperBound.x),
                        0.5F * (box.lowerBound.y + box.upperBound.y),
                        0.5F * (box.upperBound.x - box.lowerBound.x) + pad,
                        0.5F * (box.upperBound.y - box.lowerBound.y) + pad});
      }
    }
  }
  // Map walls do not move: the grid over them is built once, not every scan.
  if (fresh_ != statics_) {
    statics_.swap(fresh_);
    if (uses_grid()) build_grid();
  }
}

void RayCaster::build_grid() {
  double lx = std::numeric_limits<double>::infinity(), ly = lx, ux = -lx, uy = -lx;
  ++grid_builds_;
  for (const Candidate& c : statics_) {
    lx = std::min(lx, double(c.cx) - c.hx);
    ly = std::min(ly, double(c.cy) - c.hy);
    ux = std::max(ux, double(c.cx) + c.hx);
    uy = std::max(uy, double(c.cy) + c.hy);
  }
  const double w = ux - lx, h = uy - ly;
  // About two cells per candidate, square cells.
  cell_ = std::max(std::sqrt(w * h / (2.0 * double(statics_.size()))), 1e-3);
  cell_ = std::max({cell_, w / kMaxCells, h / kMaxCells});
  nx_ = std::clamp(int(std::ceil(w / cell_)), 1, kMaxCells);
  ny_ = std::clamp(int(std::ceil(h / cell_)), 1, kMaxCells);
  gx_ = lx;
  gy_ = ly;
  const auto range = [&](const Candidate& c, int& i0, int& i1, int& j0, int& j1) {
    i0 = std::clamp(int(std::floor((double(c.cx) - c.hx - gx_) / cell_)), 0, nx_ - 1);
    i1 = std::clamp(int(std::floor((double(c.cx) + c.hx - gx_) / cell_)), 0, nx_ - 1);
    j0 = std::clamp(int(std::floor((double(c.cy) - c.hy - gy_) / cell_)), 0, ny_ - 1);
    j1 = std::clamp(int(std::floor((double(c.cy) + c.hy - gy_) / cell_)), 0, ny_ - 1);
  };
  start_.assign(std::size_t(nx_) * std::size_t(ny_) + 1, 0);
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  for (const Candidate& c : statics_) {
    range(c, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) ++start_[std::size_t(j * nx_ + i) + 1];
    }
  }
  for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
  items_.resize(start_.back());
  cursor_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t n = 0; n < statics_.size(); ++n) {
    range(statics_[n], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) items_[cursor_[std::size_t(j * nx_ + i)]++] = std::uint32_t(n);
    }
  }
  stamp_.assign(statics_.size(), 0);
  casts_ = 0;
}

RayCaster::Segment RayCaster::segment(const b2Vec2& p1, const b2Vec2& p2) {
  Segment s;
  s.input.p1 = p1;
  s.input.p2 = p2;
  s.input.maxFraction = 1.0F;  // as b2World::RayCast starts; the fraction does not depend on it
  s.mx = 0.5F * (p1.x + p2.x);
  s.my = 0.5F * (p1.y + p2.y);
  s.ex = 0.5F * std::abs(p2.x - p1.x);
  s.ey = 0.5F * std::abs(p2.y - p1.y);
  s.vx = -(p2.y - p1.y);
  s.vy = p2.x - p1.x;
  s.avx = std::abs(s.vx);
  s.avy = std::abs(s.vy);
  return s;
}

// Conservative: false only when the segment misses the padded box (box-box, then separating
// axis along the segment's normal, as b2DynamicTree::RayCast does).
inline bool RayCaster::may_touch(const Candidate& c, const Segment& s) {
  if (std::abs(s.mx - c.cx) > s.ex + c.hx || std::abs(s.my - c.cy) > s.ey + c.hy) return false;
  const float sep = s.vx * (s.input.p1.x - c.cx) + s.vy * (s.input.p1.y - c.cy);
  return std::abs(sep) <= s.avx * c.hx + s.avy * c.hy;
}

inline void RayCaster::test(const Candidate& c, const Segment& s, float& best) const {
  if (!may_touch(c, s)) return;
  b2RayCastOutput out;  // Box2D's own ray cast of the child: the fraction b2World::RayCast gets
  if (c.fixture->RayCast(&out, s.input, c.child) && out.fraction < best) best = out.fraction;
}

float RayCaster::cast(const b2Vec2& p1, const b2Vec2& p2) {
  const Segment s = segment(p1, p2);
  float best = kNoHit;
  for (const Candidate& c : movers_) test(c, s, best);
  if (uses_grid()) return cast_grid(s, best);
  for (const Candidate& c : statics_) test(c, s, best);
  return best;
}

// Walks the grid cells the segment crosses in order (Amanatides-Woo), testing each candidate
// once, and stops at the first cell whose exit lies beyond the closest hit so far (`best` comes in
// from the moving bodies): a candidate hit closer would have its hit point, and so its padded box,
// in a cell already walked.
float RayCaster::cast_grid(const Segment& s, float best) {
  if (++casts_ == 0) {  // wrapped: forget the old stamps
    std::fill(stamp_.begin(), stamp_.end(), 0);
    casts_ = 1;
  }
  const double px = s.input.p1.x, py = s.input.p1.y;
  const double dx = double(s.input.p2.x) - px, dy = double(s.input.p2.y) - py;
  const double wx = nx_ * cell_, wy = ny_ * cell_;
  double t0 = 0.0, t1 = 1.0;
  const auto clip = [&](double p, double d, double lo, double len) {
    if (d == 0.0) return p >= lo && p <= lo + len;
    double ta = (lo - p) / d, tb = (lo + len - p) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    return t0 <= t1;
  };
  if (!clip(px, dx, gx_, wx) || !clip(py, dy, gy_, wy)) return best;
  int i = std::clamp(int(std::floor((px + t0 * dx - gx_) / cell_)), 0, nx_ - 1);
  int j = std::clamp(int(std::floor((py + t0 * dy - gy_) / cell_)), 0, ny_ - 1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int si = dx > 0 ? 1 : -1, sj = dy > 0 ? 1 : -1;
  double tx = dx == 0 ? kInf : (gx_ + (i + (dx > 0)) * cell_ - px) / dx;
  double ty = dy == 0 ? kInf : (gy_ + (j + (dy > 0)) * cell_ - py) / dy;
  const double tdx = dx == 0 ? kInf : cell_ / std::abs(dx);
  const double tdy = dy == 0 ? kInf : cell_ / std::abs(dy);
  for (;;) {
    const std::size_t c = std::size_t(j * nx_ + i);
    for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
      const std::uint32_t n = items_[k];
      if (stamp_[n] == casts_) continue;
      stamp_[n] = casts_;
      test(statics_[n], s, best);
    }
    const double exit = std::min(tx, ty);
    if (double(best) <= exit || exit >= t1) break;
    if (tx < ty) {
      i += si;
      if (i < 0 || i >= nx_) break;
      tx += tdx;
    } else {
      j += sj;
      if (j < 0 || j >= ny_) break;
      ty += tdy;
    }
  }
  return best;
}

}  // namespace carril::sim
