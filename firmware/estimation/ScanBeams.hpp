#pragma once
// Which returns of a scan Monte Carlo localisation uses, in one place: the update, the fit check
// and the walls check must pick the same beams.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "firmware/core/Geometry.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// A usable return: finite and within [range_min, min(range_max, max_range)) [m]. Quiet
// comparisons: a driver's NaN limit must not trap.
struct ValidReturn {
  float rmin = 0.0F, rmax = 0.0F;
  ValidReturn(const hal::LaserScan& scan, double max_range_m)
      : rmin(scan.range_min_m), rmax(std::fmin(scan.range_max_m, float(max_range_m))) {}
  bool operator()(float r) const {
    return std::isfinite(r) && std::isgreaterequal(r, rmin) && std::isless(r, rmax);
  }
};

// Calls visit(i) for the beams an update weighs (before beam skipping): of the scan's valid
// returns, up to max_beams evenly spaced, the k-th being the valid one of rank
// (2k + 1) nv / (2 nb). Returns how many were visited.
template <typename Visit>
int for_each_weighed_beam(const hal::LaserScan& scan, double max_range_m, int max_beams,
                          Visit&& visit) {
  const ValidReturn valid(scan, max_range_m);
  const int count = std::min(int(scan.count), hal::kMaxScanBeams);
  long nv = 0;
  for (int i = 0; i < count; ++i) nv += valid(scan.ranges_m[std::size_t(i)]) ? 1 : 0;
  if (nv == 0 || max_beams <= 0) return 0;
  const long nb = std::min(nv, long(max_beams));
  long rank = 0, k = 0;
  for (int i = 0; i < count && k < nb; ++i) {
    if (!valid(scan.ranges_m[std::size_t(i)])) continue;
    if (rank++ != (2 * k + 1) * nv / (2 * nb)) continue;
    ++k;
    visit(i);
  }
  return int(k);
}

// A return as an endpoint in the robot frame, in cells (the unit the likelihood field's lookups
// take): the lidar at `mount` in the robot frame [m, m, rad], cells of 1 / inv_res metres.
class BeamEndpoints {
 public:
  BeamEndpoints(const Pose2& mount, double inv_res)
      : mount_(mount), mc_(std::cos(mount.yaw)), ms_(std::sin(mount.yaw)), inv_res_(inv_res) {}
  // Return i of `scan` [cells].
  void operator()(const hal::LaserScan& scan, int i, float& x, float& y) const {
    const double a = double(scan.angle_min_rad) + double(i) * double(scan.angle_increment_rad);
    const double r = double(scan.ranges_m[std::size_t(i)]);
    const double lx = r * std::cos(a), ly = r * std::sin(a);
    x = float((mount_.x + mc_ * lx - ms_ * ly) * inv_res_);
    y = float((mount_.y + ms_ * lx + mc_ * ly) * inv_res_);
  }

 private:
  Pose2 mount_;
  double mc_, ms_, inv_res_;
};

}  // namespace carril::fw
