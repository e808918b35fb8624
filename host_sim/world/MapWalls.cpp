#include "host_sim/world/MapWalls.hpp"

#include <cstddef>

#include "firmware/mapping/CostValues.hpp"

namespace carril::sim {

namespace {

// Runs of occupied cells along the rows of a w x h grid (cell (a, b) occupied when
// occupied(a, b)), each merged with the run of the same span in the row below when there is one.
// Rectangles in (a, b) cell coordinates.
template <typename Occupied>
std::vector<WallRect> merge_runs(int w, int h, Occupied occupied) {
  std::vector<WallRect> done;
  std::vector<WallRect> open, next;  // rectangles reaching the previous row, by run start
  for (int b = 0; b < h; ++b) {
    next.clear();
    std::size_t k = 0;  // open rectangles before k start left of the current run
    for (int a = 0; a < w;) {
      if (!occupied(a, b)) {
        ++a;
        continue;
      }
      const int a0 = a;
      while (a < w && occupied(a, b)) ++a;
      // The open rectangles are sorted by start, like the runs: close those left behind.
      while (k < open.size() && open[k].i0 < a0) done.push_back(open[k++]);
      if (k < open.size() && open[k].i0 == a0 && open[k].i1 == a) {
        WallRect r = open[k++];
        r.j1 = b + 1;
        next.push_back(r);
      } else {
        next.push_back({a0, b, a, b + 1});
      }
    }
    while (k < open.size()) done.push_back(open[k++]);
    open.swap(next);
  }
  done.insert(done.end(), open.begin(), open.end());
  return done;
}

}  // namespace

std::vector<WallRect> merge_occupied_cells(const loader::OccupancyMapData& map) {
  const int nx = map.info.nx, ny = map.info.ny;
  if (nx <= 0 || ny <= 0 ||
      map.cells.size() != static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)) {
    return {};
  }
  auto occupied = [&](int i, int j) {
    return map.cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) +
                     static_cast<std::size_t>(i)] == fw::cost::kLethal;
  };
  std::vector<WallRect> rows = merge_runs(nx, ny, occupied);
  std::vector<WallRect> cols = merge_runs(ny, nx, [&](int j, int i) { return occupied(i, j); });
  if (cols.size() < rows.size()) {
    // Runs went along columns: swap the axes back.
    for (WallRect& r : cols) r = {r.j0, r.i0, r.j1, r.i1};
    rows.swap(cols);
  }
  const double res = map.info.resolution_m, ox = map.info.origin_x_m, oy = map.info.origin_y_m;
  for (WallRect& r : rows) {
    r.min_x = ox + r.i0 * res;
    r.max_x = ox + r.i1 * res;
    r.min_y = oy + r.j0 * res;
    r.max_y = oy + r.j1 * res;
  }
  return rows;
}

b2Body* add_map_walls(b2World& world, const std::vector<WallRect>& rects) {
  if (rects.empty()) return nullptr;
  b2BodyDef bd;  // static, at the world origin: the fixtures carry the world coordinates
  b2Body* body = world.CreateBody(&bd);
  for (const WallRect& r : rects) {
    b2PolygonShape s;
    s.SetAsBox(float((r.max_x - r.min_x) / 2), float((r.max_y - r.min_y) / 2),
               b2Vec2(float((r.min_x + r.max_x) / 2), float((r.min_y + r.max_y) / 2)), 0.0F);
    body->CreateFixture(&s, 0.0F);
  }
  return body;
}

}  // namespace carril::sim
