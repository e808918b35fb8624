#include "firmware/mapping/TerrainAnalysis.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "host_sim/alloc/AllocCounter.hpp"
#include "tests/unit/mapping/SyntheticTerrain.hpp"

namespace carril::fw {
namespace {

struct Fixture {
  RollingGrid<ElevationCell> grid;
  TerrainAnalysis ta;
  explicit Fixture(const TerrainConfig& cfg = TerrainConfig{}) {
    EXPECT_TRUE(grid.init(80, 80, 0.05, ElevationCell{}));
    grid.recenter(0.0, 0.0);  // window [-2, 2) m
    EXPECT_TRUE(ta.init(cfg, 80, 80, 0.05).is_ok());
  }
  std::size_t at(double x, double y) const {
    return ta.index(grid.cell_of(x) - grid.origin_cx(), grid.cell_of(y) - grid.origin_cy());
  }
};

TEST(TerrainAnalysisTest, TiltedPlaneGivesItsSlope) {
  // Shallow and steep (the slope's arctangent is reflected beyond 45 deg).
  for (const double deg : {0.5, 5.0, 30.0, 44.0, 46.0, 60.0, 80.0}) {
    SCOPED_TRACE(deg);
    Fixture f;
    const double a = synth::deg(deg), dir = 0.5;  // rising toward azimuth 0.5 rad
    synth::fill(f.grid, [&](double x, double y) {
      return std::tan(a) * (x * std::cos(dir) + y * std::sin(dir));
    });
    f.ta.compute(f.grid);
    for (int ly = 5; ly < 75; ++ly)
      for (int lx = 5; lx < 75; ++lx) {
        const std::size_t i = f.ta.index(lx, ly);
        ASSERT_EQ(f.ta.status()[i], TerrainStatus::kValid);
        ASSERT_NEAR(f.ta.slope_rad()[i], a, synth::deg(0.05));
        ASSERT_NEAR(std::atan2(-f.ta.normal_y()[i], -f.ta.normal_x()[i]), dir, 0.01);
        if (deg < 10.0) ASSERT_LT(f.ta.step_up_m()[i], 0.02F);
      }
  }
}

TEST(TerrainAnalysisTest, StepUpOnTheLowSideStepDownOnTheHighSide) {
  Fixture f;
  synth::fill(f.grid, synth::step(0.0, 0.2));
  f.ta.compute(f.grid);
  EXPECT_NEAR(f.ta.step_up_m()[f.at(-0.03, 0.0)], 0.2F, 1e-5F);
  EXPECT_NEAR(f.ta.step_down_m()[f.at(-0.03, 0.0)], 0.0F, 1e-5F);
  EXPECT_NEAR(f.ta.step_down_m()[f.at(0.03, 0.0)], 0.2F, 1e-5F);
  EXPECT_NEAR(f.ta.step_up_m()[f.at(0.03, 0.0)], 0.0F, 1e-5F);
  // Beyond the step radius (0.1 m) nothing.
  EXPECT_NEAR(f.ta.step_up_m()[f.at(-0.18, 0.0)], 0.0F, 1e-5F);
  EXPECT_NEAR(f.ta.step_down_m()[f.at(0.18, 0.0)], 0.0F, 1e-5F);
}

TEST(TerrainAnalysisTest, CubeSidesAreSteps) {
  Fixture f;
  synth::fill(f.grid, synth::box(0.5, 0.5, 1.0, 1.0));
  f.ta.compute(f.grid);
  EXPECT_NEAR(f.ta.step_up_m()[f.at(-0.03, 0.5)], 1.0F, 1e-5F);   // ground at its face
  EXPECT_NEAR(f.ta.step_down_m()[f.at(0.03, 0.5)], 1.0F, 1e-5F);  // its edge
  EXPECT_NEAR(f.ta.slope_rad()[f.at(0.5, 0.5)], 0.0F, 1e-4F);     // its top is flat
}

TEST(TerrainAnalysisTest, UnobservedAndTooSparseCells) {
  Fixture f;
  f.grid.at(f.grid.cell_of(0.0), f.grid.cell_of(0.0)) = ElevationCell{0.0F, 1e-4F};
  for (int i = -10; i <= 10; ++i)  // one line of cells: no plane
    f.grid.at(f.grid.cell_of(1.0) + i, f.grid.cell_of(1.0)) = ElevationCell{0.1F, 1e-4F};
  f.ta.compute(f.grid);
  EXPECT_EQ(f.ta.status()[f.at(-1.0, -1.0)], TerrainStatus::kUnobserved);
  EXPECT_EQ(f.ta.status()[f.at(0.0, 0.0)], TerrainStatus::kNotEnoughData);
  EXPECT_EQ(f.ta.status()[f.at(1.0, 1.0)], TerrainStatus::kNotEnoughData);
}

// A 20 cm drop seen from above: the ground just beyond the edge is hidden. The edge cell
// measures the drop across the unseen gap; cells away from any gap do not.
TEST(TerrainAnalysisTest, DropAcrossAnUnseenGap) {
  Fixture f;
  synth::fill(f.grid, synth::step(0.0, -0.2));
  for (int ly = 0; ly < 80; ++ly)
    for (int lx = 0; lx < 80; ++lx) {
      const double x = f.grid.center_of(f.grid.origin_cx() + lx);
      if (x > 0.0 && x < 0.3) f.grid.local(lx, ly) = ElevationCell{};  // the shadow
    }
  f.ta.compute(f.grid);
  EXPECT_NEAR(f.ta.step_down_m()[f.at(-0.03, 0.0)], 0.0F, 1e-5F);  // no lower cell near
  EXPECT_NEAR(f.ta.drop_m()[f.at(-0.03, 0.0)], 0.2F, 1e-5F);
  EXPECT_NEAR(f.ta.drop_m()[f.at(-0.5, 0.0)], 0.0F, 1e-5F);
  EXPECT_EQ(f.ta.status()[f.at(0.1, 0.0)], TerrainStatus::kUnobserved);
}

// A cell the lidar's rings skipped on a 13 cm plateau, 0.3 m from its edge: not a shadow, so
// its neighbours measure no drop toward the lower ground beyond the edge (a single hole once
// made a lethal blob in the middle of a traversable hill).
TEST(TerrainAnalysisTest, AnIsolatedHoleIsNoFrontier) {
  Fixture f;
  synth::fill(f.grid, [](double, double y) { return y > -0.5 ? 0.13 : 0.0; });
  f.grid.local(40, 36) = ElevationCell{};  // y = -0.175 m
  f.grid.local(44, 36) = ElevationCell{};  // two of the 25 cells of a box
  f.grid.local(45, 37) = ElevationCell{};
  f.ta.compute(f.grid);
  for (int ly = 30; ly < 42; ++ly)
    for (int lx = 35; lx < 50; ++lx)
      if (f.grid.local(lx, ly).observed()) ASSERT_EQ(f.ta.drop_m()[f.ta.index(lx, ly)], 0.0F);
  // A shadow five cells wide is one.
  for (int lx = 20; lx < 25; ++lx)
    for (int ly = 30; ly < 42; ++ly) f.grid.local(lx, ly) = ElevationCell{};
  f.ta.compute(f.grid);
  EXPECT_NEAR(f.ta.drop_m()[f.ta.index(19, 36)], 0.13F, 1e-5F);
}

TEST(TerrainAnalysisTest, SubRectangleMatchesTheWholeWindow) {
  Fixture whole, part;
  auto s = [](double x, double y) { return 0.1 * std::sin(3 * x) + 0.05 * std::cos(4 * y); };
  synth::fill(whole.grid, s);
  synth::fill(part.grid, s);
  whole.ta.compute(whole.grid);
  part.ta.compute(part.grid, 20, 30, 25, 10);
  for (int ly = 30; ly < 40; ++ly)
    for (int lx = 20; lx < 45; ++lx) {
      const std::size_t i = whole.ta.index(lx, ly);
      ASSERT_NEAR(part.ta.slope_rad()[i], whole.ta.slope_rad()[i], 1e-5F);
      ASSERT_EQ(part.ta.step_up_m()[i], whole.ta.step_up_m()[i]);
    }
}

TEST(TerrainAnalysisTest, ClosedFormEigenvectorMatchesEigen) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    Eigen::Matrix3d b;
    for (int i = 0; i < 9; ++i) b(i / 3, i % 3) = g(rng);
    const Eigen::Matrix3d a = b * b.transpose();
    double n[3], mid = 0.0;
    ASSERT_TRUE(smallest_eigenvector(a(0, 0), a(0, 1), a(0, 2), a(1, 1), a(1, 2), a(2, 2), n, mid));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(a);
    const Eigen::Vector3d e = es.eigenvectors().col(0);
    ASSERT_NEAR(std::fabs(e.dot(Eigen::Vector3d(n[0], n[1], n[2]))), 1.0, 1e-6);
    ASSERT_NEAR(mid, es.eigenvalues()(1), 1e-8 * (1.0 + es.eigenvalues()(2)));
  }
}

TEST(TerrainAnalysisTest, ComputeDoesNotAllocate) {
  Fixture f;
  synth::fill(f.grid, synth::ramp(-1.0, 2.0, 10.0));
  alloc::begin_window();
  f.ta.compute(f.grid);
  f.ta.compute(f.grid, 10, 10, 20, 20);
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
}

}  // namespace
}  // namespace carril::fw
