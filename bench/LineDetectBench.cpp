// Tape perception per 640x480 frame: carril's LineDetector against the thesis's OpenCV pipeline
// (GaussianBlur 5x5, cvtColor HSV, inRange, erode x2, dilate x2, findContours, contourArea,
// moments, fitLine), one thread each, cycling over the same eight frames rendered by the
// simulator's camera (tests/unit/perception/PerceptionFrames.hpp). carril's detect() also builds
// and labels the end-mark mask, which the OpenCV pipeline measured here does not.
//
//   ./build/host/bench/bench_line_detect --benchmark_repetitions=9 \
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "firmware/health/SensorHealth.hpp"
#include "tests/unit/perception/PerceptionFrames.hpp"

namespace {

using carril::fw::LineDetection;
using carril::fw::LineDetector;
namespace test = carril::test;

struct Frames {
  std::vector<std::unique_ptr<test::RenderedFrame>> frames;
  std::vector<carril::fw::LineDetectorConfig> configs;
};

const Frames& frames() {
  static const Frames f = [] {
    Frames r;
    std::uint64_t seed = 1;
    for (const test::FrameCase& fc : test::bench_cases()) {
      r.frames.push_back(test::render_case(fc, seed++));
      r.configs.push_back(test::config_for(fc.color));
    }
    return r;
  }();
  return f;
}

void carril_detect(benchmark::State& st, int decimation) {
  const Frames& f = frames();
  // One detector per frame (the frames come from two robots and look for two colours).
  std::vector<std::unique_ptr<LineDetector>> det;
  for (std::size_t i = 0; i < f.frames.size(); ++i) {
    carril::fw::LineDetectorConfig cfg = f.configs[i];
    cfg.decimation = decimation;
    det.push_back(std::make_unique<LineDetector>(f.frames[i]->camera(), cfg));
  }
  LineDetection out;
  std::size_t i = 0;
  for (auto _ : st) {
    det[i]->detect(*f.frames[i]->frame, out);
    benchmark::DoNotOptimize(out);
    i = i + 1 == f.frames.size() ? 0 : i + 1;
  }
  st.SetItemsProcessed(st.iterations());
}

void opencv_detect(benchmark::State& st) {
  const Frames& f = frames();
  test::OracleBuffers buf;
  std::size_t i = 0;
  for (auto _ : st) {
    const carril::fw::LineDetectorConfig& cfg = f.configs[i];
    test::OracleResult r = test::opencv_detect(*f.frames[i]->frame, cfg.line, 6000.0, buf);
    benchmark::DoNotOptimize(r);
    i = i + 1 == f.frames.size() ? 0 : i + 1;
  }
  st.SetItemsProcessed(st.iterations());
}

// The camera health check that runs on every frame beside detect(): spread and content hash
// over a sparse pixel grid (firmware/health/SensorHealth.cpp).
void frame_health(benchmark::State& st) {
  const Frames& f = frames();
  carril::fw::FrameHealth h{carril::fw::FrameHealthConfig{}};
  carril::fw::Pose2 pose;
  std::size_t i = 0;
  for (auto _ : st) {
    pose.x += 0.01;
    benchmark::DoNotOptimize(h.add(*f.frames[i]->frame, pose));
    i = i + 1 == f.frames.size() ? 0 : i + 1;
  }
  st.SetItemsProcessed(st.iterations());
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::RegisterBenchmark("BM_LineDetect_Carril/640x480", [](benchmark::State& st) {
    carril_detect(st, 2);
  })->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_LineDetect_OpenCV/640x480", opencv_detect)
      ->Unit(benchmark::kMicrosecond);
  // The other decimations, for reference (the default is 2).
  benchmark::RegisterBenchmark("BM_LineDetect_Carril_Decimation1/640x480",
                               [](benchmark::State& st) { carril_detect(st, 1); })
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_LineDetect_Carril_Decimation4/640x480",
                               [](benchmark::State& st) { carril_detect(st, 4); })
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_FrameHealth/640x480", frame_health)
      ->Unit(benchmark::kMicrosecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  frames();  // render before timing
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
