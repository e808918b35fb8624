#include "firmware/mapping/CoverageGrid.hpp"

#include <cmath>

namespace carril::fw {

namespace {
double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}
// Sub-steps of a turn: the tool's ends move at most half a cell per sub-step.
constexpr int kMaxSubsteps = 256;
}  // namespace

Status CoverageGrid::init(const MapInfo& info, double max_step_m) {
  if (Status s = info.validate(); !s) return s;
  if (!(std::isfinite(max_step_m) && max_step_m > 0.0)) {
    return Status::error("coverage.max_step_m: %g m, expected a finite number > 0", max_step_m);
  }
  info_ = info;
  max_step_m_ = max_step_m;
  n_ = static_cast<std::size_t>(info.nx) * static_cast<std::size_t>(info.ny);
  counts_ = std::make_unique<std::uint8_t[]>(n_);
  mask_ = std::make_unique<std::uint8_t[]>(n_);
  stamp_ = std::make_unique<std::uint32_t[]>(n_);
  set_mask(nullptr);
  clear();
  return Status::ok();
}

void CoverageGrid::clear() {
  for (std::size_t k = 0; k < n_; ++k) {
    counts_[k] = 0;
    stamp_[k] = 0;
  }
  pass_ = 1;
  covered_ = overlapped_ = swept_ = 0;
}

void CoverageGrid::set_mask(const std::uint8_t* mask) {
  mask_cells_ = covered_ = overlapped_ = 0;
  for (std::size_t k = 0; k < n_; ++k) {
    mask_[k] = (mask == nullptr || mask[k] != 0) ? 1 : 0;
    if (mask_[k] == 0) continue;
    ++mask_cells_;
    if (counts_[k] >= 1) ++covered_;
    if (counts_[k] >= 2) ++overlapped_;
  }
}

double CoverageGrid::covered_fraction() const {
  return mask_cells_ == 0 ? 0.0 : double(covered_) / double(mask_cells_);
}

double CoverageGrid::overlap_fraction() const {
  return covered_ == 0 ? 0.0 : double(overlapped_) / double(covered_);
}

bool CoverageGrid::next_unswept(std::size_t& index) const {
  for (std::size_t k = index; k < n_; ++k) {
    if (mask_[k] != 0 && counts_[k] == 0) {
      index = k;
      return true;
    }
  }
  return false;
}

void CoverageGrid::sweep(const Pose2& from, const Pose2& to, double tool_width_m) {
  if (!ready() || !(tool_width_m > 0.0) || !std::isfinite(from.x) || !std::isfinite(from.y) ||
      !std::isfinite(from.yaw) || !std::isfinite(to.x) || !std::isfinite(to.y) ||
      !std::isfinite(to.yaw)) {
    return;
  }
  if (++pass_ == 0) {  // after 2^32 calls: start the stamps again
    for (std::size_t k = 0; k < n_; ++k) stamp_[k] = 0;
    pass_ = 2;
  }
  const double half = 0.5 * tool_width_m;
  const double step = std::hypot(to.x - from.x, to.y - from.y);
  if (step <= max_step_m_) {
    const double dyaw = wrap_angle(to.yaw - from.yaw);
    const double subs = std::ceil(std::fabs(dyaw) * half / (0.5 * info_.resolution_m));
    const int n = subs < 1.0 ? 1 : (subs > kMaxSubsteps ? kMaxSubsteps : int(subs));
    Pose2 a = from;
    for (int k = 1; k <= n; ++k) {
      const double t = double(k) / n;
      const Pose2 b{from.x + t * (to.x - from.x), from.y + t * (to.y - from.y),
                    from.yaw + t * dyaw};
      mark_step(a, b, half);
      a = b;
    }
  }
  mark_strip(to, half);
}

// The area the tool segment swept from a to b (a small step): the quadrilateral between its two
// positions, or, when the two positions cross (a turn about a point on the tool), the two
// triangles between the crossing point and the ends.
void CoverageGrid::mark_step(const Pose2& a, const Pose2& b, double half) {
  const Vec2 la(-std::sin(a.yaw), std::cos(a.yaw)), lb(-std::sin(b.yaw), std::cos(b.yaw));
  const Vec2 pa(a.x, a.y), pb(b.x, b.y);
  const Vec2 a0 = pa + half * la, a1 = pa - half * la;  // left and right ends at a
  const Vec2 b0 = pb + half * lb, b1 = pb - half * lb;
  const Vec2 da = a1 - a0, db = b1 - b0;
  const double den = cross(da, db);
  if (std::fabs(den) > 1e-12) {
    const double t = cross(b0 - a0, db) / den;  // along a0 -> a1
    const double u = cross(b0 - a0, da) / den;  // along b0 -> b1
    if (t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0) {
      const Vec2 c = a0 + t * da;
      const Vec2 left[3] = {c, a0, b0};
      const Vec2 right[3] = {c, a1, b1};
      mark_convex(left, 3);
      mark_convex(right, 3);
      return;
    }
  }
  const Vec2 quad[4] = {a0, b0, b1, a1};
  mark_convex(quad, 4);
}

// The tool at p as a strip one cell deep along the heading.
void CoverageGrid::mark_strip(const Pose2& p, double half) {
  const Vec2 f(std::cos(p.yaw), std::sin(p.yaw)), l(-f.y(), f.x());
  const Vec2 c(p.x, p.y);
  const double d = 0.5 * info_.resolution_m;
  const Vec2 rect[4] = {c + d * f + half * l, c - d * f + half * l, c - d * f - half * l,
                        c + d * f - half * l};
  mark_convex(rect, 4);
}

// Marks the cells whose centres lie inside the convex polygon pts[0..n) (either orientation,
// boundary included).
void CoverageGrid::mark_convex(const Vec2* pts, int n) {
  double area = 0.0;
  double x0 = pts[0].x(), x1 = x0, y0 = pts[0].y(), y1 = y0;
  for (int k = 0; k < n; ++k) {
    area += cross(pts[k], pts[(k + 1) % n]);
    x0 = std::fmin(x0, pts[k].x());
    x1 = std::fmax(x1, pts[k].x());
    y0 = std::fmin(y0, pts[k].y());
    y1 = std::fmax(y1, pts[k].y());
  }
  if (std::fabs(area) < 1e-12) return;  // degenerate: no area swept
  const double sign = area > 0.0 ? 1.0 : -1.0;
  const double res = info_.resolution_m;
  // Cells whose centres may fall inside: centre (i + 0.5) res + origin in [x0, x1].
  // Clamped before converting: a pose far off the map must not overflow int.
  const double nx = info_.nx, ny = info_.ny;
  const int i0 = int(clampd(std::ceil((x0 - info_.origin_x_m) / res - 0.5), 0.0, nx));
  const int i1 = int(clampd(std::floor((x1 - info_.origin_x_m) / res - 0.5), -1.0, nx - 1.0));
  const int j0 = int(clampd(std::ceil((y0 - info_.origin_y_m) / res - 0.5), 0.0, ny));
  const int j1 = int(clampd(std::floor((y1 - info_.origin_y_m) / res - 0.5), -1.0, ny - 1.0));
  constexpr double kEps = 1e-9;
  for (int j = j0; j <= j1; ++j) {
    const double cy = info_.origin_y_m + (j + 0.5) * res;
    for (int i = i0; i <= i1; ++i) {
      const Vec2 c(info_.origin_x_m + (i + 0.5) * res, cy);
      bool inside = true;
      for (int k = 0; k < n && inside; ++k) {
        const Vec2& p = pts[k];
        const Vec2& q = pts[(k + 1) % n];
        inside = sign * cross(q - p, c - p) >= -kEps;
      }
      if (inside) mark(index(i, j));
    }
  }
}

void CoverageGrid::mark(std::size_t k) {
  if (stamp_[k] == pass_) return;  // already counted by this call
  const bool still_under = stamp_[k] == pass_ - 1;
  stamp_[k] = pass_;
  if (still_under || counts_[k] == 255) return;
  const std::uint8_t c = ++counts_[k];
  if (c == 1) ++swept_;
  if (mask_[k] == 0) return;
  if (c == 1) ++covered_;
  if (c == 2) ++overlapped_;
}

}  // namespace carril::fw
