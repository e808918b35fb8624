#include "firmware/planning/CoverageArea.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

bool point_in_polygon(const Vec2& p, const Vec2* pts, std::size_t n) {
  bool inside = false;
  for (std::size_t k = 0, prev = n - 1; k < n; prev = k++) {
    const Vec2& a = pts[k];
    const Vec2& b = pts[prev];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

CoverageArea::CoverageArea(std::size_t max_cells)
    : capacity_(max_cells),
      centre_(new std::uint8_t[max_cells]),
      coverable_(new std::uint8_t[max_cells]),
      anchor_(new std::int32_t[max_cells]),
      best_(new std::uint16_t[max_cells]),
      queue_(new std::int32_t[max_cells]) {}

Status CoverageArea::build(const OccupancyGrid& map, const CoverageAreaConfig& cfg) {
  n_ = centre_cells_ = coverable_cells_ = 0;
  if (map.empty()) return Status::error("coverage area: no static map (mission needs map.file)");
  const MapInfo& info = map.info();
  const std::size_t n = std::size_t(info.nx) * std::size_t(info.ny);
  if (n > capacity_) {
    return Status::error("coverage area: the map has %zu cells, the buffers hold %zu", n,
                         capacity_);
  }
  const double res = info.resolution_m;
  const double margin = cfg.reach_margin_m < 0.0 ? 0.5 * res : cfg.reach_margin_m;
  Checks c("coverage");
  c.range("robot_radius_m", cfg.robot_radius_m, 0.0, 5.0, "m")
      .range("tool_width_m", cfg.tool_width_m, 0.01, 5.0, "m")
      .fail_if(cfg.polygon != nullptr && cfg.polygon_size < 3, "area",
               "a polygon needs 3 corners or more")
      .fail_if(0.5 * cfg.tool_width_m - margin < 0.0, "tool_width_m",
               "narrower than twice the reach margin (half a cell)");
  if (!c.result()) return c.result();
  info_ = info;
  n_ = n;
  reach_m_ = 0.5 * cfg.tool_width_m - margin;
  const int nx = info.nx, ny = info.ny;
  const auto idx = [nx](int i, int j) { return std::size_t(j) * std::size_t(nx) + std::size_t(i); };
  const auto in_area = [&](int i, int j) {
    return cfg.polygon == nullptr ||
           point_in_polygon(map.centre(i, j), cfg.polygon, cfg.polygon_size);
  };

  // Centre cells: free, and no occupied, unknown or outside cell within the radius (distances
  // between cell centres, as the costmap's inflation measures them: inscribed where d <= r).
  const double rc = cfg.robot_radius_m / res;
  const int r = int(std::floor(rc + (cfg.box_distance ? 0.5 : 0.0) + 1e-9));
  const int r2 = int(std::floor(rc * rc + 1e-9));
  // Within the radius of occupied cell (0, 0): by centres, or by its square's nearest point.
  const auto within = [&](int di, int dj) {
    if (!cfg.box_distance) return di * di + dj * dj <= r2;
    const double ex = std::max(std::abs(di) - 0.5, 0.0), ey = std::max(std::abs(dj) - 0.5, 0.0);
    return ex * ex + ey * ey <= rc * rc + 1e-9;
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int edge = std::min(std::min(i + 1, nx - i), std::min(j + 1, ny - j));
      centre_[idx(i, j)] = map.is_free(i, j) && edge * edge > r2 ? 1 : 0;
    }
  }
  // Only the boundary of the obstacles matters: a non-free cell with a free neighbour.
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (map.is_free(i, j)) continue;
      bool boundary = false;
      for (int dj = -1; dj <= 1 && !boundary; ++dj)
        for (int di = -1; di <= 1 && !boundary; ++di) boundary = map.is_free(i + di, j + dj);
      if (!boundary) continue;
      for (int dj = -r; dj <= r; ++dj) {
        for (int di = -r; di <= r; ++di) {
          if (within(di, dj) && map.contains(i + di, j + dj)) {
            centre_[idx(i + di, j + dj)] = 0;
          }
        }
      }
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      std::uint8_t& m = centre_[idx(i, j)];
      if (m != 0 && !in_area(i, j)) m = 0;
      centre_cells_ += m;
      coverable_[idx(i, j)] = m;
      anchor_[idx(i, j)] = m != 0 ? std::int32_t(idx(i, j)) : kNoAnchor;
      best_[idx(i, j)] = m != 0 ? 0 : 0xFFFF;
    }
  }
  if (centre_cells_ == 0) {
    return Status::error(
        "coverage area: no free cell where the robot fits (free space eroded by %.2f m%s)",
        cfg.robot_radius_m, cfg.polygon != nullptr ? ", inside the polygon" : "");
  }

  // Coverable cells: within the reach of a centre cell. The nearest centre cell of a cell outside
  // the centre set lies on that set's boundary, so only boundary centre cells paint.
  const double rr = reach_m_ / res;
  const int q = int(std::floor(rr + 1e-9));
  const int q2 = int(std::floor(rr * rr + 1e-9));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (centre_[idx(i, j)] == 0) continue;
      bool boundary = false;
      for (int dj = -1; dj <= 1 && !boundary; ++dj) {
        for (int di = -1; di <= 1 && !boundary; ++di) {
          boundary = !map.contains(i + di, j + dj) || centre_[idx(i + di, j + dj)] == 0;
        }
      }
      if (!boundary) continue;
      for (int dj = -q; dj <= q; ++dj) {
        for (int di = -q; di <= q; ++di) {
          const int d2 = di * di + dj * dj;
          const int x = i + di, y = j + dj;
          if (d2 > q2 || !map.is_free(x, y)) continue;
          const std::size_t k = idx(x, y);
          if (d2 >= best_[k] || !in_area(x, y)) continue;
          best_[k] = std::uint16_t(d2);
          anchor_[k] = std::int32_t(idx(i, j));
          coverable_[k] = 1;
        }
      }
    }
  }
  for (std::size_t k = 0; k < n_; ++k) coverable_cells_ += coverable_[k];
  return Status::ok();
}

bool CoverageArea::keep_component(int i, int j) {
  if (i < 0 || j < 0 || i >= info_.nx || j >= info_.ny) return false;
  const int nx = info_.nx, ny = info_.ny;
  const std::size_t start = std::size_t(j) * std::size_t(nx) + std::size_t(i);
  if (centre_[start] == 0) return false;
  // Breadth first over the centre cells; reached cells are marked 2.
  std::size_t head = 0, tail = 0;
  centre_[start] = 2;
  queue_[tail++] = std::int32_t(start);
  while (head < tail) {
    const std::size_t k = std::size_t(queue_[head++]);
    const int x = int(k % std::size_t(nx)), y = int(k / std::size_t(nx));
    const int nbx[4] = {x + 1, x - 1, x, x};
    const int nby[4] = {y, y, y + 1, y - 1};
    for (int m = 0; m < 4; ++m) {
      if (nbx[m] < 0 || nby[m] < 0 || nbx[m] >= nx || nby[m] >= ny) continue;
      const std::size_t u = std::size_t(nby[m]) * std::size_t(nx) + std::size_t(nbx[m]);
      if (centre_[u] != 1) continue;
      centre_[u] = 2;
      queue_[tail++] = std::int32_t(u);
    }
  }
  centre_cells_ = 0;
  for (std::size_t k = 0; k < n_; ++k) {
    centre_[k] = centre_[k] == 2 ? 1 : 0;
    centre_cells_ += centre_[k];
  }
  keep_anchored([this](std::size_t a) { return centre_[a] != 0; });
  return true;
}

}  // namespace carril::fw
