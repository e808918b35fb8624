// CoverageGrid: what a tool of a given width sweeps between poses, and the pass rule (a cell is
// counted once per separate pass, never twice while it stays under the tool).
#include "firmware/mapping/CoverageGrid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

constexpr double kRes = 0.05;

CoverageGrid make_grid(double max_step = 1.0) {
  MapInfo info;
  info.nx = 80;  // 4 x 2 m
  info.ny = 40;
  info.resolution_m = kRes;
  CoverageGrid g;
  EXPECT_TRUE(g.init(info, max_step).is_ok());
  return g;
}

// Drives straight from a to b in 4 mm steps (a 0.4 m/s robot at 100 Hz).
Pose2 drive(CoverageGrid& g, Pose2 a, const Pose2& b, double tool = 0.5) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const int steps = std::max(1, int(std::ceil(len / 0.004)));
  Pose2 at = a;
  for (int s = 1; s <= steps; ++s) {
    const Pose2 next{a.x + (b.x - a.x) * s / steps, a.y + (b.y - a.y) * s / steps, b.yaw};
    g.sweep(at, next, tool);
    at = next;
  }
  return at;
}

double cx(int i) {
  return (i + 0.5) * kRes;
}

TEST(CoverageGridTest, AStraightRunCountsEveryCellUnderTheToolOnce) {
  CoverageGrid g = make_grid();
  drive(g, Pose2{0.51, 1.0, 0.0}, Pose2{3.51, 1.0, 0.0});
  for (int j = 0; j < 40; ++j) {
    for (int i = 0; i < 80; ++i) {
      const bool across = std::fabs(cx(j) - 1.0) <= 0.25;
      const bool along = cx(i) >= 0.51 - 0.5 * kRes && cx(i) <= 3.51 + 0.5 * kRes;
      EXPECT_EQ(g.count(i, j), across && along ? 1 : 0) << i << "," << j;
    }
  }
  EXPECT_EQ(g.overlapped_cells(), 0u);
  EXPECT_EQ(g.overlap_fraction(), 0.0);
}

TEST(CoverageGridTest, DrivingBackCountsASecondPass) {
  CoverageGrid g = make_grid();
  const Pose2 end = drive(g, Pose2{0.51, 1.0, 0.0}, Pose2{3.51, 1.0, 0.0});
  // Turn on the spot, drive back on the same line.
  Pose2 at = end;
  for (int k = 1; k <= 314; ++k) {
    const Pose2 next{end.x, end.y, 0.01 * k};
    g.sweep(at, next, 0.5);
    at = next;
  }
  drive(g, at, Pose2{0.5, 1.0, kPi});
  EXPECT_EQ(g.count(40, 20), 2);  // (2.025, 1.025): far from both ends
  EXPECT_EQ(g.count(40, 15), 2);
  EXPECT_EQ(g.count(40, 26), 0);
  EXPECT_GT(g.overlap_fraction(), 0.9);  // the half disks of the turn: once
}

TEST(CoverageGridTest, StandingStillIsOnePass) {
  CoverageGrid g = make_grid();
  const Pose2 p{2.0, 1.0, 0.3};
  for (int k = 0; k < 500; ++k) g.sweep(p, p, 0.5);
  EXPECT_EQ(g.count(39, 20), 1);  // (1.975, 1.025): 1.6 cm behind the tool's centre line
  EXPECT_GT(g.swept_cells(), 5u);
  for (int k = 0; k < 80 * 40; ++k) EXPECT_LE(g.counts()[k], 1);
}

TEST(CoverageGridTest, AFullTurnOnTheSpotPassesTwiceOverItsDisk) {
  CoverageGrid g = make_grid();
  Pose2 at{2.0, 1.0, 0.0};
  for (int k = 1; k <= 629; ++k) {  // 2 pi in 0.01 rad steps (0.6 rad/s at 60 Hz)
    const Pose2 next{2.0, 1.0, 0.01 * k};
    g.sweep(at, next, 0.5);
    at = next;
  }
  // A cell 0.15 m from the centre meets the tool twice (the tool's two halves).
  EXPECT_EQ(g.count(int(2.15 / kRes), 20), 2);
  EXPECT_EQ(g.count(int(2.0 / kRes), int(1.15 / kRes)), 2);
  EXPECT_EQ(g.count(int(2.35 / kRes), 20), 0);  // beyond the tool's half width

  // One call turning 1 rad marks the two sectors the tool swept, not the ones beside them.
  CoverageGrid one = make_grid();
  one.sweep(Pose2{2.0, 1.0, 0.0}, Pose2{2.0, 1.0, 1.0}, 0.5);
  const auto polar = [&](double angle, double r) {
    return one.count(int(std::floor((2.0 + r * std::cos(angle)) / kRes)),
                     int(std::floor((1.0 + r * std::sin(angle)) / kRes)));
  };
  // The tool's left end starts at +90 deg and turns to 147 deg; the right end from -90 deg.
  EXPECT_EQ(polar(2.1, 0.2), 1);
  EXPECT_EQ(polar(-1.1, 0.2), 1);
  EXPECT_EQ(polar(0.6, 0.2), 0);
  EXPECT_EQ(polar(3.0, 0.2), 0);
}

TEST(CoverageGridTest, AJumpMarksOnlyTheToolAtTheNewPose) {
  CoverageGrid g = make_grid(0.5);
  g.sweep(Pose2{0.5, 1.0, 0.0}, Pose2{3.01, 1.0, 0.0}, 0.5);
  EXPECT_EQ(g.count(int(1.5 / kRes), 20), 0);
  EXPECT_EQ(g.count(int(3.01 / kRes), 20), 1);
  EXPECT_EQ(g.count(int(0.5 / kRes), 20), 0);
  // A pose far off the map marks nothing and does not trap.
  g.sweep(Pose2{1e12, -1e12, 0.0}, Pose2{1e12, -1e12, 1.0}, 0.5);
  g.sweep(Pose2{NAN, 0.0, 0.0}, Pose2{1.0, 1.0, 0.0}, 0.5);
}

TEST(CoverageGridTest, MaskStatisticsAndTheUnsweptCells) {
  CoverageGrid g = make_grid();
  std::vector<std::uint8_t> mask(80 * 40, 0);
  for (int j = 10; j < 30; ++j)
    for (int i = 10; i < 70; ++i) mask[std::size_t(j * 80 + i)] = 1;  // 60 x 20 cells
  g.set_mask(mask.data());
  EXPECT_EQ(g.mask_cells(), 1200u);
  drive(g, Pose2{0.0, 1.0, 0.0}, Pose2{3.99, 1.0, 0.0});  // rows 15..24 over the whole width
  EXPECT_EQ(g.covered_cells(), 600u);
  EXPECT_DOUBLE_EQ(g.covered_fraction(), 0.5);
  EXPECT_GT(g.swept_cells(), 600u);  // outside the mask too
  std::size_t k = 0;
  ASSERT_TRUE(g.next_unswept(k));
  EXPECT_EQ(k, std::size_t(10 * 80 + 10));
  std::size_t unswept = 0;
  for (k = 0; g.next_unswept(k); ++k) {
    EXPECT_TRUE(mask[k] != 0 && g.counts()[k] == 0);
    ++unswept;
  }
  EXPECT_EQ(unswept, 600u);
  g.clear();
  EXPECT_EQ(g.covered_cells(), 0u);
  EXPECT_EQ(g.mask_cells(), 1200u);
}

TEST(CoverageGridTest, SweepingDoesNotAllocate) {
  CoverageGrid g = make_grid();
  alloc::begin_window();
  const Pose2 end = drive(g, Pose2{0.5, 1.0, 0.0}, Pose2{3.5, 1.5, 0.2});
  g.sweep(end, Pose2{end.x, end.y, 3.0}, 0.5);
  std::size_t k = 0;
  g.next_unswept(k);
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0u);
}

TEST(CoverageGridTest, AnInvalidMapIsAClearError) {
  CoverageGrid g;
  MapInfo info;  // 0 x 0
  EXPECT_FALSE(g.init(info).is_ok());
  EXPECT_FALSE(g.ready());
}

}  // namespace
}  // namespace carril::fw
