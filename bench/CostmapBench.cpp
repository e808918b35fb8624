// Costmap benchmarks (issue 10): (a) InflationLayer on a 240 x 240 grid with ~5 % lethal cells
// (boxes and walls) against OpenCV's exact distance transform (DIST_L2, DIST_MASK_PRECISE) plus
// the same cost lookup per cell; both must give identical costs (checked before timing).
// (b) one ObstacleLayer update from a 541-beam scan (270 deg, 1-6 m, some +inf) plus inflation.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/InflationLayer.hpp"
#include "firmware/mapping/LayeredCostmap.hpp"

namespace {
using namespace carril::fw;
namespace hal = carril::hal;

constexpr int kN = 240;
constexpr double kRes = 0.05;

InflationConfig inflation_config() {
  InflationConfig c;
  c.inscribed_radius_m = 0.25;
  c.inflation_radius_m = 0.55;
  c.cost_scaling_factor = 10.0;
  return c;
}

// About 5 % lethal cells: random boxes and wall segments on free space.
void fill_world(RollingGrid<std::uint8_t>& g) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> pos(0, kN - 1), len(10, 60), box(2, 6);
  g.clear();
  int lethal = 0;
  while (lethal < kN * kN / 20) {
    const int x = pos(rng), y = pos(rng);
    if (rng() % 3 == 0) {  // wall, 1 cell thick
      const int l = len(rng);
      const bool horizontal = rng() % 2 == 0;
      for (int k = 0; k < l; ++k) {
        const int cx = horizontal ? x + k : x, cy = horizontal ? y : y + k;
        if (cx < kN && cy < kN && g.local(cx, cy) != cost::kLethal) {
          g.local(cx, cy) = cost::kLethal;
          ++lethal;
        }
      }
    } else {
      const int w = box(rng), h = box(rng);
      for (int dy = 0; dy < h; ++dy)
        for (int dx = 0; dx < w; ++dx)
          if (x + dx < kN && y + dy < kN && g.local(x + dx, y + dy) != cost::kLethal) {
            g.local(x + dx, y + dy) = cost::kLethal;
            ++lethal;
          }
    }
  }
}

// The reference: OpenCV distance to the nearest zero pixel (lethal), then the same table.
void opencv_inflate(const cv::Mat& src, cv::Mat& zero_at_lethal, cv::Mat& dist, cv::Mat& out,
                    const InflationLayer& inf) {
  cv::compare(src, cost::kLethal, zero_at_lethal, cv::CMP_NE);
  cv::distanceTransform(zero_at_lethal, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  for (int y = 0; y < src.rows; ++y) {
    const float* d = dist.ptr<float>(y);
    const std::uint8_t* s = src.ptr<std::uint8_t>(y);
    std::uint8_t* o = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < src.cols; ++x) {
      const float d2f = d[x] * d[x];
      const int d2 = d2f > 60000.0F ? 60000 : int(std::lround(d2f));
      const std::uint8_t c = inf.cost_of_sq_cells(d2);
      o[x] = s[x] == cost::kUnknown ? (c > 0 ? c : s[x]) : std::max(s[x], c);
    }
  }
}

struct InflationFixture {
  RollingGrid<std::uint8_t> world, out;
  InflationLayer inf;
  cv::Mat src = cv::Mat(kN, kN, CV_8UC1), mask, dist, cv_out = cv::Mat(kN, kN, CV_8UC1);
  InflationFixture() {
    world.init(kN, kN, kRes, cost::kFree);
    out.init(kN, kN, kRes, cost::kFree);
    world.move_origin(-117, 31);  // storage wraps, as on the robot
    out.move_origin(-117, 31);
    fill_world(world);
    inf.init(inflation_config(), kN, kN, kRes);
    world.copy_to(src.ptr<std::uint8_t>(0));
  }
};

// Both implementations give the same cost on every cell (distances are exact in both).
bool check_agreement() {
  InflationFixture f;
  f.inf.apply(f.world, f.out);
  opencv_inflate(f.src, f.mask, f.dist, f.cv_out, f.inf);
  cv::Mat carril(kN, kN, CV_8UC1);
  f.out.copy_to(carril.ptr<std::uint8_t>(0));
  int lethal = 0, diff = 0, maxdiff = 0;
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const int a = carril.at<std::uint8_t>(y, x), b = f.cv_out.at<std::uint8_t>(y, x);
      lethal += a == cost::kLethal;
      if (a != b) ++diff;
      maxdiff = std::max(maxdiff, std::abs(a - b));
    }
  std::printf("inflation check: %d lethal cells (%.1f %%), %d cells differ, max difference %d\n",
              lethal, 100.0 * lethal / (kN * kN), diff, maxdiff);
  return diff == 0;
}

void BM_Inflation_Carril(benchmark::State& state) {
  InflationFixture f;
  for (auto _ : state) {
    f.inf.apply(f.world, f.out);
    benchmark::DoNotOptimize(f.out.storage_row(0));
  }
}
BENCHMARK(BM_Inflation_Carril)->Unit(benchmark::kMicrosecond);

void BM_Inflation_OpenCV(benchmark::State& state) {
  InflationFixture f;
  for (auto _ : state) {
    opencv_inflate(f.src, f.mask, f.dist, f.cv_out, f.inf);
    benchmark::DoNotOptimize(f.cv_out.data);
  }
}
BENCHMARK(BM_Inflation_OpenCV)->Unit(benchmark::kMicrosecond);

// (b) A 12 m window at 5 cm (240 x 240), one 541-beam scan, then the master and its inflation.
void BM_ObstacleUpdatePlusInflation(benchmark::State& state) {
  LayeredCostmap cm;
  CostmapConfig cfg;
  cfg.inflation = inflation_config();
  if (!cm.init(cfg).is_ok()) std::abort();
  cm.recenter(0.0, 0.0);
  hal::LaserScan scan;
  scan.count = 541;
  scan.angle_min_rad = float(-0.75 * kPi);
  scan.angle_increment_rad = float(1.5 * kPi / 540.0);
  scan.range_min_m = 0.05F;
  scan.range_max_m = 30.0F;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> range(1.0F, 6.0F);
  for (int i = 0; i < 541; ++i)
    scan.ranges_m[std::size_t(i)] =
        i % 10 == 0 ? std::numeric_limits<float>::infinity() : range(rng);
  cm.update_obstacles(scan, Pose2{0.1, 0.1, 0.3});
  cm.update_master();
  for (auto _ : state) {
    cm.update_obstacles(scan, Pose2{0.1, 0.1, 0.3});
    cm.update_master();
    benchmark::DoNotOptimize(cm.master().storage_row(0));
  }
}
BENCHMARK(BM_ObstacleUpdatePlusInflation)->Unit(benchmark::kMicrosecond);

// The scan update alone, to split the figure above.
void BM_ObstacleUpdateOnly(benchmark::State& state) {
  LayeredCostmap cm;
  if (!cm.init(CostmapConfig{}).is_ok()) std::abort();
  hal::LaserScan scan;
  scan.count = 541;
  scan.angle_min_rad = float(-0.75 * kPi);
  scan.angle_increment_rad = float(1.5 * kPi / 540.0);
  scan.range_max_m = 30.0F;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> range(1.0F, 6.0F);
  for (int i = 0; i < 541; ++i)
    scan.ranges_m[std::size_t(i)] =
        i % 10 == 0 ? std::numeric_limits<float>::infinity() : range(rng);
  for (auto _ : state) {
    cm.update_obstacles(scan, Pose2{0.1, 0.1, 0.3});
    benchmark::DoNotOptimize(cm.obstacle_layer().storage_row(0));
  }
}
BENCHMARK(BM_ObstacleUpdateOnly)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  if (!check_agreement()) {
    std::fprintf(stderr, "carril and OpenCV inflation disagree\n");
    return 1;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
