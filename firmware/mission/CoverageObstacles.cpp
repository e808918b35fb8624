// The coverage mission's view of obstacles: the static map's walls are the mission's own area
// (CoverageArea); the live costmap adds what the map does not show. A lethal costmap cell within
// mapped_wall_tolerance_m of a mapped wall is taken as that wall: lidar returns off a wall's face
// land in the free cell before it about half the time, and the costmap's inflation of such a
// cell would otherwise close the lanes the area lays along every wall. See CoverageMission.hpp.
#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/CoverageMission.hpp"

namespace carril::fw {

// Init time: O(cells * (tolerance / resolution)^2).
void CoverageMission::build_mapped_mask() {
  const int nx = map_.nx(), ny = map_.ny();
  const double res = map_.resolution();
  const int r = int(std::floor(cfg_.mapped_wall_tolerance_m / res + 1e-9));
  const double r2 = (cfg_.mapped_wall_tolerance_m / res) * (cfg_.mapped_wall_tolerance_m / res);
  for (std::size_t k = 0; k < area_.size(); ++k) mapped_[k] = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (map_.is_free(i, j)) continue;
      for (int dj = -r; dj <= r; ++dj) {
        for (int di = -r; di <= r; ++di) {
          if (double(di * di + dj * dj) > r2 + 1e-9 || !map_.contains(i + di, j + dj)) continue;
          mapped_[cell_index(i + di, j + dj)] = 1;
        }
      }
    }
  }
}

// Costmap cell (cx, cy) is lethal and no mapped wall: an obstacle the map does not show.
bool CoverageMission::unmapped_lethal(int cx, int cy) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  if (!m.contains(cx, cy) || m.at(cx, cy) != cost::kLethal) return false;
  int i = 0, j = 0;
  if (!map_.cell_of(m.center_of(cx), m.center_of(cy), i, j)) return false;  // off the map: a wall
  return mapped_[cell_index(i, j)] == 0;
}

// How far the robot's centre keeps from an unmapped obstacle's cell: the inscribed radius plus
// wall_clearance_m, as from the mapped walls [m]. With the radius alone the planner led transits
// through gaps a centimetre wider than the body, where pure pursuit's cut corners touched the
// obstacle, the wheels slipped and the pose estimate ran off (docs/performance.md).
double CoverageMission::obstacle_reach_m() const {
  return std::min(footprint_.half_length_m, footprint_.half_width_m) + cfg_.wall_clearance_m;
}

// plan_costs_ (the static area) gains the costmap's graded costs (transits keep off walls) and
// the unmapped obstacles, each widened by obstacle_reach_m(). O(cells) plus the obstacles'
// disks.
void CoverageMission::overlay_unmapped() {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  if (!m.ready()) return;
  const int nx = map_.nx(), ny = map_.ny();
  const double res = map_.resolution();
  const double radius = obstacle_reach_m() / res;
  const int r = int(std::ceil(radius));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const std::size_t k = cell_index(i, j);
      const Vec2 w = map_.centre(i, j);
      int cx = 0, cy = 0;
      if (!m.world_to_cell(w.x(), w.y(), cx, cy)) continue;
      const std::uint8_t mc = m.at(cx, cy);
      if (cost::passable(mc) && plan_costs_[k] != cost::kLethal) {
        plan_costs_[k] = std::max(plan_costs_[k], mc);
      }
      if (mc != cost::kLethal || mapped_[k] != 0) continue;
      for (int dj = -r; dj <= r; ++dj) {
        for (int di = -r; di <= r; ++di) {
          if (double(di * di + dj * dj) > radius * radius || !map_.contains(i + di, j + dj)) {
            continue;
          }
          plan_costs_[cell_index(i + di, j + dj)] = cost::kLethal;
        }
      }
    }
  }
}

// An unmapped obstacle within obstacle_reach_m() of p: the body standing there would touch it, or
// come closer than the clearance the mission keeps.
bool CoverageMission::blocked_at(const Vec2& p) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  if (!m.ready()) return false;
  const double radius = obstacle_reach_m();
  const int n = int(std::ceil(radius / m.resolution()));
  const int cx0 = m.cell_of(p.x()), cy0 = m.cell_of(p.y());
  for (int cy = cy0 - n; cy <= cy0 + n; ++cy) {
    for (int cx = cx0 - n; cx <= cx0 + n; ++cx) {
      // d <= r as the costmap's inflation takes it (a lane a whole number of cells away is in).
      if (std::hypot(m.center_of(cx) - p.x(), m.center_of(cy) - p.y()) > radius + 1e-6) continue;
      if (unmapped_lethal(cx, cy)) return true;
    }
  }
  return false;
}

// A lethal costmap cell whose centre lies within (inscribed radius + margin) of the robot's,
// within 60 degrees of its heading (forward) or of its back (backward). The body is taken as its
// inscribed circle and distances between cell centres, as the planner's area and the costmap's
// inscribed cells take them: a robot on any cell the planner allows is clear by at least half a
// cell's diagonal less than the margin.
// Unless any_lethal, only unmapped obstacles count: the area keeps the robot off the mapped walls.
bool CoverageMission::lethal_near(const Pose2& pose, double margin, bool forward,
                                  bool any_lethal) const {
  const RollingGrid<std::uint8_t>& m = costmap().master();
  if (!m.ready() || !std::isfinite(pose.x) || !std::isfinite(pose.y)) return false;
  const double reach = std::min(footprint_.half_length_m, footprint_.half_width_m) + margin;
  const int n = static_cast<int>(std::ceil(reach / m.resolution())) + 1;
  const double hx = std::cos(pose.yaw) * (forward ? 1.0 : -1.0);
  const double hy = std::sin(pose.yaw) * (forward ? 1.0 : -1.0);
  const int cx0 = m.cell_of(pose.x), cy0 = m.cell_of(pose.y);
  for (int cy = cy0 - n; cy <= cy0 + n; ++cy) {
    for (int cx = cx0 - n; cx <= cx0 + n; ++cx) {
      if (!m.contains(cx, cy) || m.at(cx, cy) != cost::kLethal) continue;
      if (!any_lethal && !unmapped_lethal(cx, cy)) continue;
      const double dx = m.center_of(cx) - pose.x, dy = m.center_of(cy) - pose.y;
      const double d = std::hypot(dx, dy);
      if (d <= reach && dx * hx + dy * hy >= 0.5 * d) return true;  // cos >= 0.5: +-60 deg
    }
  }
  return false;
}

}  // namespace carril::fw
