#include "firmware/mapping/StaticLayer.hpp"

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

Status StaticLayer::init(int nx, int ny, double resolution_m) {
  if (grid_.init(nx, ny, resolution_m, cost::kUnknown)) return Status::ok();
  return Status::error("mapping: the static layer's %d x %d cells at %g m could not be set up", nx,
                       ny, resolution_m);
}

void StaticLayer::place(const OccupancyGrid& map, double x, double y) {
  grid_.recenter(x, y);
  for (int ly = 0; ly < grid_.ny(); ++ly) {
    const int cy = grid_.origin_cy() + ly;
    for (int lx = 0; lx < grid_.nx(); ++lx) {
      const int cx = grid_.origin_cx() + lx;
      int i = 0, j = 0;
      grid_.local(lx, ly) = map.cell_of(grid_.center_of(cx), grid_.center_of(cy), i, j)
                                ? map.at(i, j)
                                : cost::kUnknown;
    }
  }
}

}  // namespace carril::fw
