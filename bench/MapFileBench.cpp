// Saved elevation maps (issue 10): the carril code against a reference in the same binary.
//   Crc32: crc32_ieee (byte-wise table) vs zlib's crc32 (slicing, the reference).
//   Encode: the file's bytes field by field (portable) vs memcpy of the cell array (the layout a
//   struct dump would give on a little-endian host; the lower bound).
//   Load: load_elevation_map (read, CRC, checks) of a 1000 x 1000 map (a 50 m square at 5 cm).
#include <benchmark/benchmark.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "loader/ElevationMapFile.hpp"

namespace {

using carril::loader::ElevationMapData;

constexpr std::uint32_t kSide = 1000;

ElevationMapData make_map() {
  ElevationMapData m;
  m.resolution_m = 0.05;
  m.nx = kSide;
  m.ny = kSide;
  m.cells.resize(std::size_t{kSide} * kSide);
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    m.cells[i].height_m = static_cast<float>(i % 977) * 1e-3F;
    m.cells[i].variance_m2 = i % 5 == 0 ? 0.0F : 1e-4F;
  }
  return m;
}

const ElevationMapData& map() {
  static const ElevationMapData m = make_map();
  return m;
}

const std::string& encoded() {
  static const std::string bytes = [] {
    std::string error;
    return *carril::loader::encode_elevation_map(map(), error);
  }();
  return bytes;
}

void BM_Crc32_Carril(benchmark::State& state) {
  const std::string& b = encoded();
  for (auto _ : state) benchmark::DoNotOptimize(carril::loader::crc32_ieee(b.data(), b.size()));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * b.size()));
}
BENCHMARK(BM_Crc32_Carril)->Unit(benchmark::kMillisecond);

void BM_Crc32_Zlib(benchmark::State& state) {
  const std::string& b = encoded();
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        crc32(0L, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(b.size())));
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * b.size()));
}
BENCHMARK(BM_Crc32_Zlib)->Unit(benchmark::kMillisecond);

void BM_Encode_FieldByField(benchmark::State& state) {
  std::string error;
  for (auto _ : state) {
    auto bytes = carril::loader::encode_elevation_map(map(), error);
    benchmark::DoNotOptimize(bytes->data());
  }
}
BENCHMARK(BM_Encode_FieldByField)->Unit(benchmark::kMillisecond);

// Reference: header + memcpy of the cells, no CRC (what a struct dump costs, at best).
void BM_Encode_Memcpy(benchmark::State& state) {
  const auto& cells = map().cells;
  constexpr std::size_t n = std::size_t{kSide} * kSide * sizeof(carril::fw::ElevationCell);
  for (auto _ : state) {
    std::vector<char> bytes(carril::loader::kElevationMapHeaderBytes + n + 4);
    const auto* src = reinterpret_cast<const char*>(cells.data());
    std::copy(src, src + n, bytes.begin() + carril::loader::kElevationMapHeaderBytes);
    benchmark::DoNotOptimize(bytes.data());
  }
}
BENCHMARK(BM_Encode_Memcpy)->Unit(benchmark::kMillisecond);

void BM_Load_1000x1000(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("carril_bench_map_" + std::to_string(::getpid()) + ".cem");
  if (auto err = carril::loader::save_elevation_map(path.string(), map())) {
    state.SkipWithError(err->c_str());
    return;
  }
  for (auto _ : state) {
    auto r = carril::loader::load_elevation_map(path.string(), std::uint64_t{kSide} * kSide);
    if (!r.ok()) state.SkipWithError(r.error.c_str());
    benchmark::DoNotOptimize(r.map.cells.data());
  }
  std::filesystem::remove(path);
}
BENCHMARK(BM_Load_1000x1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
