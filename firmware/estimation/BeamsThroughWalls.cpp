#include "firmware/estimation/BeamsThroughWalls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "firmware/estimation/ScanBeams.hpp"
#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {

// Whether the segment (x0, y0) -> (x1, y1), in cell units from the map's lower-left corner, touches
// an occupied cell: Amanatides and Woo's traversal, every cell the segment enters, in order.
bool crosses_occupied(const OccupancyGrid& map, double x0, double y0, double x1, double y1) {
  int i = int(std::floor(x0)), j = int(std::floor(y0));
  const int i1 = int(std::floor(x1)), j1 = int(std::floor(y1));
  const double dx = x1 - x0, dy = y1 - y0;
  const int si = dx > 0.0 ? 1 : -1, sj = dy > 0.0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Parameter t in [0, 1] along the segment at which the next column and row boundary lie, and
  // the step of t per cell.
  const double di = dx != 0.0 ? std::abs(1.0 / dx) : kInf;
  const double dj = dy != 0.0 ? std::abs(1.0 / dy) : kInf;
  double ti = dx > 0.0 ? (double(i + 1) - x0) * di : dx < 0.0 ? (x0 - double(i)) * di : kInf;
  double tj = dy > 0.0 ? (double(j + 1) - y0) * dj : dy < 0.0 ? (y0 - double(j)) * dj : kInf;
  // A segment crosses at most |i1 - i| + |j1 - j| boundaries: the bound ends the walk even where
  // rounding would step past the end cell.
  for (int n = std::abs(i1 - i) + std::abs(j1 - j); n >= 0; --n) {
    if (map.at(i, j) == cost::kLethal) return true;
    if (ti < tj) {
      i += si;
      ti += di;
    } else {
      j += sj;
      tj += dj;
    }
  }
  return false;
}

}  // namespace

BeamsThroughWalls beams_through_walls(const OccupancyGrid& map, const hal::LaserScan& scan,
                                      const Pose2& pose, const Pose2& laser_mount, int max_beams,
                                      double max_range_m, double margin_m) {
  BeamsThroughWalls out;
  if (map.empty()) return out;
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const double inv_res = 1.0 / map.resolution();
  // The sensor in cell units.
  const double sx =
      (pose.x + c * laser_mount.x - s * laser_mount.y - map.info().origin_x_m) * inv_res;
  const double sy =
      (pose.y + s * laser_mount.x + c * laser_mount.y - map.info().origin_y_m) * inv_res;
  const double yaw0 = pose.yaw + laser_mount.yaw;
  out.checked = for_each_weighed_beam(scan, max_range_m, max_beams, [&](int k) {
    const double r = double(scan.ranges_m[std::size_t(k)]);
    if (r <= 2.0 * margin_m) return;  // nothing left between the margins
    const double a =
        yaw0 + double(scan.angle_min_rad) + double(k) * double(scan.angle_increment_rad);
    const double ux = std::cos(a) * inv_res, uy = std::sin(a) * inv_res;
    const double t0 = margin_m, t1 = r - margin_m;
    if (crosses_occupied(map, sx + t0 * ux, sy + t0 * uy, sx + t1 * ux, sy + t1 * uy)) {
      ++out.through;
    }
  });
  return out;
}

}  // namespace carril::fw
