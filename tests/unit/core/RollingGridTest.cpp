#include "firmware/core/RollingGrid.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

// A window of global indices written with a value derived from the index, so moved cells can
// be recognised.
std::uint8_t tag(int cx, int cy) {
  return std::uint8_t((cx * 7 + cy * 13) & 0x7F);
}

void tag_all(RollingGrid<std::uint8_t>& g) {
  for (int ly = 0; ly < g.ny(); ++ly)
    for (int lx = 0; lx < g.nx(); ++lx)
      g.local(lx, ly) = tag(g.origin_cx() + lx, g.origin_cy() + ly);
}

TEST(RollingGridTest, InitRejectsBadSizes) {
  RollingGrid<std::uint8_t> g;
  EXPECT_FALSE(g.init(0, 10, 0.05, 255));
  EXPECT_FALSE(g.init(10, 10, 0.0, 255));
  EXPECT_TRUE(g.init(10, 12, 0.05, 255));
  EXPECT_EQ(g.nx(), 10);
  EXPECT_EQ(g.ny(), 12);
  EXPECT_EQ(g.local(3, 4), 255);
}

TEST(RollingGridTest, WorldToCellUsesFloorAndTheWindow) {
  RollingGrid<std::uint8_t> g;
  ASSERT_TRUE(g.init(20, 20, 0.05, 0));
  g.recenter(0.0, 0.0);  // window [-10, 10) cells
  int cx = 0, cy = 0;
  EXPECT_TRUE(g.world_to_cell(-0.01, 0.01, cx, cy));
  EXPECT_EQ(cx, -1);
  EXPECT_EQ(cy, 0);
  EXPECT_TRUE(g.world_to_cell(-0.5, 0.49, cx, cy));
  EXPECT_FALSE(g.world_to_cell(0.5, 0.0, cx, cy));  // cell 10 is just outside
  EXPECT_FALSE(g.world_to_cell(std::nan(""), 0.0, cx, cy));
}

// After any move, cells that stayed in the window keep their value and cells that entered hold
// the fill value: checked against a reference for moves in every direction, small and large.
TEST(RollingGridTest, MovesKeepOverlapAndResetEnteringCells) {
  RollingGrid<std::uint8_t> g;
  ASSERT_TRUE(g.init(17, 11, 0.1, 255));
  const int moves[][2] = {{1, 0},  {0, 1},   {-3, 2},  {5, -4},  {-16, 10}, {16, -10},
                          {17, 0}, {0, -11}, {40, 40}, {-2, -2}, {0, 0}};
  g.move_origin(-5, 3);
  tag_all(g);
  for (const auto& m : moves) {
    const int ox = g.origin_cx(), oy = g.origin_cy();
    g.move_origin(ox + m[0], oy + m[1]);
    for (int ly = 0; ly < g.ny(); ++ly)
      for (int lx = 0; lx < g.nx(); ++lx) {
        const int cx = g.origin_cx() + lx, cy = g.origin_cy() + ly;
        const bool was_inside = cx >= ox && cx < ox + g.nx() && cy >= oy && cy < oy + g.ny();
        ASSERT_EQ(g.at(cx, cy), was_inside ? tag(cx, cy) : 255)
            << "move " << m[0] << "," << m[1] << " cell " << cx << "," << cy;
      }
    tag_all(g);
  }
}

TEST(RollingGridTest, CopyToIsRowMajorFromTheLowerLeftCell) {
  RollingGrid<std::uint8_t> g;
  ASSERT_TRUE(g.init(9, 7, 0.1, 0));
  g.move_origin(-4, 12);
  tag_all(g);
  g.move_origin(-1, 10);  // storage now wrapped in both axes
  tag_all(g);
  std::vector<std::uint8_t> out(9 * 7);
  g.copy_to(out.data());
  for (int ly = 0; ly < 7; ++ly)
    for (int lx = 0; lx < 9; ++lx) EXPECT_EQ(out[ly * 9 + lx], tag(-1 + lx, 10 + ly));
  // The row spans agree with the same layout.
  for (int ly = 0; ly < 7; ++ly)
    for (int lx = 0; lx < 9; ++lx)
      EXPECT_EQ(g.storage_row(ly)[(g.column_offset() + lx) % 9], tag(-1 + lx, 10 + ly));
}

TEST(RollingGridTest, MovingNeverAllocates) {
  RollingGrid<std::uint8_t> g;
  ASSERT_TRUE(g.init(240, 240, 0.05, 255));
  const auto before = alloc::count_total();
  for (int i = 0; i < 500; ++i) g.recenter(0.013 * i, -0.007 * i);
  EXPECT_EQ(alloc::count_total(), before);
}

}  // namespace
}  // namespace carril::fw
