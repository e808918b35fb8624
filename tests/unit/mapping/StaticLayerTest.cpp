// The static occupancy map (OccupancyGrid) and the static costmap layer read from it.
#include "firmware/mapping/StaticLayer.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {
namespace {

// A 2 x 1 m map at 0.1 m whose origin is off the cell grid by 0.03 m, a wall along x = 1 m.
std::vector<std::uint8_t> test_cells(MapInfo& info) {
  info = {20, 10, 0.1, -0.97, -0.47};
  std::vector<std::uint8_t> cells(200, cost::kFree);
  for (int j = 0; j < 10; ++j) cells[j * 20 + 19] = cost::kLethal;
  cells[0] = cost::kUnknown;
  return cells;
}

TEST(OccupancyGrid, AssignChecksValuesAndCapacity) {
  MapInfo info;
  std::vector<std::uint8_t> cells = test_cells(info);
  OccupancyGrid small(199);
  const Status big = small.assign(info, cells.data());
  ASSERT_FALSE(big.is_ok());
  EXPECT_NE(std::string(big.message()).find("20 x 10 = 200 cells"), std::string::npos)
      << big.message();
  OccupancyGrid g(200);
  cells[45] = 100;
  const Status bad = g.assign(info, cells.data());
  ASSERT_FALSE(bad.is_ok());
  EXPECT_NE(std::string(bad.message()).find("cell (5, 2) holds 100"), std::string::npos)
      << bad.message();
  cells[45] = cost::kFree;
  ASSERT_TRUE(g.assign(info, cells.data()).is_ok());
  int i = 0, j = 0;
  EXPECT_TRUE(g.cell_of(-0.97 + 1.95, -0.47 + 0.05, i, j));
  EXPECT_EQ(i, 19);
  EXPECT_EQ(j, 0);
  EXPECT_EQ(g.at(i, j), cost::kLethal);
  EXPECT_FALSE(g.cell_of(1e30, 0.0, i, j));
  EXPECT_EQ(g.at(-1, 0), cost::kUnknown);
  info.resolution_m = 0.0;
  EXPECT_FALSE(g.assign(info, cells.data()).is_ok());
}

TEST(StaticLayer, EveryWindowCellReadsTheMapCellUnderItsCentre) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = test_cells(info);
  OccupancyGrid map(200);
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  StaticLayer layer;
  ASSERT_TRUE(layer.init(24, 14, 0.1).is_ok());
  // A window that cannot be allocated is an error naming it, not a silent false.
  StaticLayer bad;
  const Status s = bad.init(0, 14, 0.1);
  EXPECT_FALSE(s.is_ok());
  EXPECT_STREQ(s.message(),
               "mapping: the static layer's 0 x 14 cells at 0.1 m could not be set up");
  layer.place(map, 0.03, 0.03);
  const RollingGrid<std::uint8_t>& g = layer.grid();
  int walls = 0, unknown_inside = 0;
  for (int cy = g.origin_cy(); cy < g.origin_cy() + g.ny(); ++cy) {
    for (int cx = g.origin_cx(); cx < g.origin_cx() + g.nx(); ++cx) {
      int i = 0, j = 0;
      const bool in = map.cell_of(g.center_of(cx), g.center_of(cy), i, j);
      const std::uint8_t want = in ? cells[std::size_t(j) * 20 + std::size_t(i)] : cost::kUnknown;
      ASSERT_EQ(g.at(cx, cy), want) << cx << ", " << cy;
      if (in && want == cost::kLethal) ++walls;
      if (in && want == cost::kUnknown) ++unknown_inside;
    }
  }
  EXPECT_EQ(walls, 10);  // the wall column, once per row
  EXPECT_EQ(unknown_inside, 1);
  // The wall at x = 0.93..1.03 reads lethal in the window, free space beside it free.
  int cx = 0, cy = 0;
  ASSERT_TRUE(g.world_to_cell(0.98, 0.0, cx, cy));
  EXPECT_EQ(g.at(cx, cy), cost::kLethal);
  ASSERT_TRUE(g.world_to_cell(0.5, 0.0, cx, cy));
  EXPECT_EQ(g.at(cx, cy), cost::kFree);
}

}  // namespace
}  // namespace carril::fw
