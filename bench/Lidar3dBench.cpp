// One simulated HDL-32E sweep (32 x 1800 beams, 20 m) over a terrain scene: carril's Lidar3dSim
// (adaptive step growing with range, bisection, early exits above max_height) against the
// reference brute force (a uniform 1 cm march along every beam, no early exit).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "host_sim/sensors/Lidar3dSim.hpp"

namespace {

using carril::sim::HeightQuery;

// A 40 x 40 m height grid at 0.05 m (nearest cell), centred on the sensor: a 5 deg ramp, a 20 cm
// step down, a trench and a few 1 m boxes.
class GridScene : public HeightQuery {
 public:
  GridScene() : h_(std::size_t(kN) * kN, 0.0F) {
    for (int j = 0; j < kN; ++j) {
      for (int i = 0; i < kN; ++i) {
        const double x = (i + 0.5) * kRes - kHalf, y = (j + 0.5) * kRes - kHalf;
        double z = 0.0;
        if (x > 3 && x < 9 && std::fabs(y) < 2) z = std::tan(5 * M_PI / 180) * (x - 3);
        if (x < -4) z = -0.2;
        if (y > 5 && y < 6) z = -0.5;
        for (double bx : {-8.0, 2.0, 6.0})
          if (std::fabs(x - bx) < 0.5 && std::fabs(y + 3) < 0.5) z = 1.0;
        h_[std::size_t(j) * kN + std::size_t(i)] = float(z);
      }
    }
  }
  double height_at(double x, double y) const override {
    const int i = int(std::floor((x + kHalf) / kRes)), j = int(std::floor((y + kHalf) / kRes));
    if (i < 0 || j < 0 || i >= kN || j >= kN) return 0.0;
    return h_[std::size_t(j) * kN + std::size_t(i)];
  }
  double max_height() const override { return 1.0; }
  double min_height() const override { return -0.5; }

 private:
  static constexpr int kN = 800;
  static constexpr double kRes = 0.05, kHalf = 20.0;
  std::vector<float> h_;
};

carril::sim::Lidar3dConfig hdl32() {
  carril::sim::Lidar3dConfig c;
  c.sensor.present = true;
  c.sensor.z_m = 0.6;
  return c;
}

void BM_Lidar3dSim_Sweep(benchmark::State& state) {
  GridScene scene;
  carril::sim::Lidar3dSim sim(hdl32(), 1);
  auto cloud = std::make_unique<carril::hal::PointCloud>();
  for (auto _ : state) {
    sim.render(scene, {}, 0, *cloud);
    benchmark::DoNotOptimize(cloud->count);
  }
  state.counters["points"] = cloud->count;
  state.counters["queries"] = double(sim.last_queries());
}
BENCHMARK(BM_Lidar3dSim_Sweep)->Unit(benchmark::kMillisecond);

// Reference: every beam marched at a uniform 1 cm from the sensor to 20 m, first crossing wins.
void BM_Reference_UniformMarch1cm(benchmark::State& state) {
  GridScene scene;
  const carril::sim::Lidar3dConfig c = hdl32();
  carril::sim::Lidar3dSim geom(c, 1);  // only for its ring and azimuth angles
  auto cloud = std::make_unique<carril::hal::PointCloud>();
  for (auto _ : state) {
    std::uint32_t n = 0;
    for (int a = 0; a < c.sensor.azimuths; ++a) {
      const double az = geom.azimuth_rad(a);
      for (int r = 0; r < c.sensor.rings; ++r) {
        const double e = geom.ring_elevation_rad(r);
        const double ux = std::cos(e) * std::cos(az), uy = std::cos(e) * std::sin(az),
                     uz = std::sin(e);
        for (double t = 0.0; t <= c.sensor.range_max_m; t += 0.01) {
          if (c.sensor.z_m + uz * t < scene.height_at(ux * t, uy * t)) {
            if (t >= c.sensor.range_min_m) {
              cloud->points[n++] = {float(ux * t), float(uy * t), float(uz * t)};
            }
            break;
          }
        }
      }
    }
    cloud->count = n;
    benchmark::DoNotOptimize(cloud->count);
  }
  state.counters["points"] = cloud->count;
}
BENCHMARK(BM_Reference_UniformMarch1cm)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
