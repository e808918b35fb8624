// carril_costmap: looks into saved elevation maps (docs/map-formats.md).
//   carril_costmap info FILE                  header fields, observed cells, height range
//   carril_costmap heights FILE OUT.png [S]   observed heights as an 8-bit grey PNG (top row =
//                                             highest y; black = never observed; S px per cell)
//   carril_costmap derive FILE ROBOT.yaml OUT  the costmap of the robot described by ROBOT.yaml
//                                             (its traversability: section and body width) on
//                                             this map, as the firmware derives it: OUT.pgm +
//                                             OUT.yaml (map_server) and OUT.png
// Exit status: 0 ok, 1 bad file or I/O error, 2 usage.
#include <png.h>

#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/InflationLayer.hpp"
#include "firmware/mapping/TerrainAnalysis.hpp"
#include "firmware/mapping/TraversabilityLayer.hpp"
#include "loader/AtomicWrite.hpp"
#include "loader/CostmapExport.hpp"
#include "loader/CostmapPng.hpp"
#include "loader/ElevationMapFile.hpp"
#include "loader/StrictYaml.hpp"
#include "loader/YamlPrecheck.hpp"

namespace {

using carril::loader::ElevationMapData;

// A saved map this tool reads at most: 2^28 cells is 2 GiB of cells, beyond any site survey.
constexpr std::uint64_t kMaxCells = std::uint64_t{1} << 28;
constexpr int kMaxScale = 16;
// PNGs this tool writes at most: libpng's own limit on a side, and 2^28 pixels (256 MiB of grey).
constexpr std::uint64_t kMaxImageSide = 1'000'000;
constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 28;
// What derive holds per cell (elevation, terrain analysis, traversability, inflation, costmap,
// the exported copies and the preview at scale 2), for the memory check before it starts [bytes].
constexpr std::uint64_t kDeriveBytesPerCell = 96;

// Blocks SIGINT, SIGTERM and SIGHUP for its lifetime; one that came meanwhile is delivered at
// the end of the scope.
class SignalsHeld {
 public:
  SignalsHeld() {
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigaddset(&s, SIGTERM);
    sigaddset(&s, SIGHUP);
    sigprocmask(SIG_BLOCK, &s, &old_);
  }
  ~SignalsHeld() { sigprocmask(SIG_SETMASK, &old_, nullptr); }
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t old_{};
};

struct HeightRange {
  std::uint64_t observed = 0;
  double min_m = std::numeric_limits<double>::infinity();
  double max_m = -std::numeric_limits<double>::infinity();
};

HeightRange height_range(const ElevationMapData& m) {
  HeightRange r;
  for (const auto& c : m.cells) {
    if (!c.observed()) continue;
    ++r.observed;
    r.min_m = std::fmin(r.min_m, static_cast<double>(c.height_m));
    r.max_m = std::fmax(r.max_m, static_cast<double>(c.height_m));
  }
  return r;
}

int info(const std::string& path, const ElevationMapData& m) {
  const HeightRange r = height_range(m);
  const std::uint64_t total = m.cells.size();
  std::printf("file:        %s\n", path.c_str());
  std::printf("format:      CARRILEM version %u\n", carril::loader::kElevationMapVersion);
  std::printf("frame:       %s\n", m.frame.c_str());
  std::printf("resolution:  %.6g m\n", m.resolution_m);
  std::printf("size:        %u x %u cells (%.6g x %.6g m)\n", m.nx, m.ny, m.nx * m.resolution_m,
              m.ny * m.resolution_m);
  std::printf("origin:      (%.6g, %.6g) m, lower-left corner of cell (0, 0)\n", m.origin_x_m,
              m.origin_y_m);
  std::printf("observed:    %llu of %llu cells (%.1f%%)\n",
              static_cast<unsigned long long>(r.observed), static_cast<unsigned long long>(total),
              100.0 * static_cast<double>(r.observed) / static_cast<double>(total));
  if (r.observed > 0) std::printf("heights:     %.4f .. %.4f m\n", r.min_m, r.max_m);
  return 0;
}

// What the tool may allocate [bytes]: half the machine's memory, and 3/4 of an address-space
// limit (ulimit -v) when one is set.
std::uint64_t memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  std::uint64_t budget = pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) / 2
                                               : std::numeric_limits<std::uint64_t>::max();
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    budget = std::min<std::uint64_t>(budget, std::uint64_t(as.rlim_cur) / 4 * 3);
  }
  return budget;
}

// Checked before allocating (a valid map at a large SCALE must get an error, not bad_alloc).
bool image_fits(std::uint64_t nx, std::uint64_t ny, int scale, const char* what) {
  const std::uint64_t w = nx * std::uint64_t(scale), h = ny * std::uint64_t(scale);
  // The grey image and libpng's output buffer, about twice the pixels.
  if (w <= kMaxImageSide && h <= kMaxImageSide && w * h <= kMaxImagePixels &&
      2 * w * h <= memory_budget()) {
    return true;
  }
  std::fprintf(stderr,
               "carril_costmap: %s: %llu x %llu cells at scale %d is %llu x %llu pixels; a PNG of "
               "this tool has at most %llu pixels a side, %llu in all, and twice its pixels "
               "within the %llu MiB it may use%s\n",
               what, static_cast<unsigned long long>(nx), static_cast<unsigned long long>(ny),
               scale, static_cast<unsigned long long>(w), static_cast<unsigned long long>(h),
               static_cast<unsigned long long>(kMaxImageSide),
               static_cast<unsigned long long>(kMaxImagePixels),
               static_cast<unsigned long long>(memory_budget() >> 20),
               scale > 1 ? " (try a smaller SCALE)" : "");
  return false;
}

int heights(const ElevationMapData& m, const std::string& out, int scale) {
  if (!image_fits(m.nx, m.ny, scale, "heights")) return 1;
  const HeightRange r = height_range(m);
  const double span = r.max_m - r.min_m;
  const auto s = static_cast<std::size_t>(scale);
  const std::size_t width = m.nx * s, height = m.ny * s;
  std::vector<std::uint8_t> grey(width * height, 0);
  for (std::size_t y = 0; y < height; ++y) {
    const std::size_t row = m.ny - 1 - y / s;  // top row = highest y
    for (std::size_t x = 0; x < width; ++x) {
      const auto& c = m.cells[row * m.nx + x / s];
      if (!c.observed()) continue;  // black
      // Lowest observed height 1, highest 255 (a flat map is mid grey).
      const double t = span > 0.0 ? (static_cast<double>(c.height_m) - r.min_m) / span : 0.5;
      grey[y * width + x] = static_cast<std::uint8_t>(1 + std::lround(t * 254.0));
    }
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_GRAY;
  png_alloc_size_t size = 0;
  std::string bytes;
  if (png_image_write_to_memory(&image, nullptr, &size, 0, grey.data(), 0, nullptr) != 0) {
    bytes.resize(size);
    if (png_image_write_to_memory(&image, bytes.data(), &size, 0, grey.data(), 0, nullptr) == 0) {
      size = 0;
    }
  }
  if (size == 0) {
    std::fprintf(stderr, "%s: libpng: %s\n", out.c_str(), image.message);
    png_image_free(&image);
    return 1;
  }
  bytes.resize(size);
  if (const auto err = carril::loader::write_file_atomically(out, bytes)) {
    std::fprintf(stderr, "%s\n", err->c_str());
    return 1;
  }
  std::printf("%s: %zu x %zu px, %llu observed cells, heights %.4f .. %.4f m -> grey 1 .. 255\n",
              out.c_str(), width, height, static_cast<unsigned long long>(r.observed),
              r.observed > 0 ? r.min_m : 0.0, r.observed > 0 ? r.max_m : 0.0);
  return 0;
}

// The robot's traversability limits and body width, from its robot file. Only those keys are
// read; each must be a plain number in range (the robot loader checks the whole file).
bool read_profile(const std::string& path, carril::fw::TraversabilityProfile& p, double& width_m,
                  std::string& error) {
  YAML::Node root;
  try {
    const std::string text = carril::loader::strict::read_file(path);
    if (const std::string e = carril::loader::strict::precheck_yaml(text); !e.empty()) {
      error = path + ":" + e;
      return false;
    }
    root = YAML::Load(text);
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
    return false;
  }
  auto number = [&](const YAML::Node& n, const std::string& key, double lo, double hi,
                    double& out) {
    if (!n || !n.IsScalar()) {
      error = path + ": " + key + ": missing (expected a number in [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "])";
      return false;
    }
    try {
      out = n.as<double>();
    } catch (const YAML::Exception&) {
      error = path + ": " + key + ": expected a number, got " + n.Scalar();
      return false;
    }
    if (!(out >= lo && out <= hi)) {
      error = path + ": " + key + ": expected a number in [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "], got " + n.Scalar();
      return false;
    }
    return true;
  };
  const YAML::Node t = root["traversability"];
  if (!t || !t.IsMap()) {
    error = path + ": traversability: missing section (a robot file, config/robots/*.yaml)";
    return false;
  }
  return number(t["max_slope_deg"], "traversability.max_slope_deg", 0.0, 60.0, p.max_slope_deg) &&
         number(t["max_step_up_m"], "traversability.max_step_up_m", 0.0, 1.0, p.max_step_up_m) &&
         number(t["max_step_down_m"], "traversability.max_step_down_m", 0.0, 1.0,
                p.max_step_down_m) &&
         number(root["body"] ? root["body"]["width_m"] : YAML::Node(), "body.width_m", 0.05, 10.0,
                width_m);
}

int derive(const ElevationMapData& m, const std::string& robot, const std::string& out) {
  using namespace carril::fw;
  TraversabilityProfile profile;
  double width_m = 0.5;
  std::string error;
  if (!read_profile(robot, profile, width_m, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  if (const Status st = profile.validate(); !st) {
    std::fprintf(stderr, "%s: %s\n", robot.c_str(), st.message());
    return 1;
  }
  // Sized before anything is allocated: against the preview's limits and this machine's memory.
  if (!image_fits(m.nx, m.ny, 2, "derive (its OUT.png preview)")) return 1;
  const std::uint64_t cells = std::uint64_t(m.nx) * m.ny;
  const std::uint64_t budget = memory_budget();
  if (cells * kDeriveBytesPerCell > budget) {
    std::fprintf(stderr,
                 "carril_costmap: derive: %u x %u cells need about %llu MiB, more than the %llu "
                 "MiB it may use (half this machine's memory, 3/4 of its address-space limit)\n",
                 m.nx, m.ny, static_cast<unsigned long long>(cells * kDeriveBytesPerCell >> 20),
                 static_cast<unsigned long long>(budget >> 20));
    return 1;
  }
  const int nx = static_cast<int>(m.nx), ny = static_cast<int>(m.ny);
  const double res = m.resolution_m;
  RollingGrid<ElevationCell> elevation;
  if (!elevation.init(nx, ny, res, ElevationCell{})) return 1;
  elevation.move_origin(static_cast<int>(std::lround(m.origin_x_m / res)),
                        static_cast<int>(std::lround(m.origin_y_m / res)));
  for (int ly = 0; ly < ny; ++ly)
    for (int lx = 0; lx < nx; ++lx) elevation.local(lx, ly) = m.cells[std::size_t(ly) * nx + lx];
  TerrainAnalysis analysis;
  TraversabilityLayer traversability;
  InflationLayer inflation;
  InflationConfig ic;
  ic.inscribed_radius_m = 0.5 * width_m;
  ic.inflation_radius_m = std::fmax(0.55, 0.5 * width_m + 0.3);
  RollingGrid<std::uint8_t> costmap;
  if (!analysis.init(TerrainConfig{}, nx, ny, res) || !traversability.init(nx, ny, res) ||
      !inflation.init(ic, nx, ny, res) || !costmap.init(nx, ny, res, cost::kUnknown)) {
    std::fprintf(stderr, "carril_costmap: cannot size the grids for %d x %d cells\n", nx, ny);
    return 1;
  }
  analysis.compute(elevation);
  traversability.update(analysis, profile);
  costmap.move_origin(elevation.origin_cx(), elevation.origin_cy());
  inflation.apply(traversability.grid(), costmap);
  std::vector<std::uint8_t> costs(std::size_t(nx) * std::size_t(ny));
  costmap.copy_to(costs.data());
  const carril::loader::CostmapGeometry g{m.nx, m.ny, res, m.origin_x_m, m.origin_y_m};
  // A stopping signal waits until the pair is written: it ends the tool right after, with the
  // new pair complete and no temporary behind (a kill -9 leaves the old pair or the new one).
  const SignalsHeld held;
  if (auto e = carril::loader::export_costmap_pgm(out, costs.data(), g)) {
    std::fprintf(stderr, "%s\n", e->c_str());
    return 1;
  }
  if (auto e = carril::loader::export_costmap_png(out + ".png", costs.data(), g, 2)) {
    std::fprintf(stderr, "%s\n", e->c_str());
    return 1;
  }
  std::size_t lethal = 0, unknown = 0, passable = 0;
  for (const std::uint8_t c : costs) {
    if (c == cost::kLethal)
      ++lethal;
    else if (c == cost::kUnknown)
      ++unknown;
    else if (cost::passable(c))
      ++passable;
  }
  std::printf("%s: profile max slope %.3g deg, step up %.3g m, step down %.3g m, width %.3g m\n",
              robot.c_str(), profile.max_slope_deg, profile.max_step_up_m, profile.max_step_down_m,
              width_m);
  std::printf("wrote %s.yaml with its image, %s.png: %zu passable, %zu lethal, %zu unknown cells\n",
              out.c_str(), out.c_str(), passable, lethal, unknown);
  return 0;
}

int usage() {
  std::fprintf(stderr,
               "usage: carril_costmap info FILE\n"
               "       carril_costmap heights FILE OUT.png [SCALE 1..%d]\n"
               "       carril_costmap derive FILE ROBOT.yaml OUT\n",
               kMaxScale);
  return 2;
}

}  // namespace

static int run_tool(int argc, char** argv);

int main(int argc, char** argv) {
  try {
    return run_tool(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "carril_costmap: out of memory (files already there are left as they were)\n");
    return 1;
  }
}

static int run_tool(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string cmd = argv[1];
  const std::string path = argv[2];
  if (!((cmd == "info" && argc == 3) || (cmd == "heights" && (argc == 4 || argc == 5)) ||
        (cmd == "derive" && argc == 5))) {
    return usage();
  }
  int scale = 1;
  if (argc == 5 && cmd == "heights") {
    char* end = nullptr;
    const long v = std::strtol(argv[4], &end, 10);
    if (end == argv[4] || *end != '\0' || v < 1 || v > kMaxScale) return usage();
    scale = static_cast<int>(v);
  }
  const auto loaded = carril::loader::load_elevation_map(path, kMaxCells);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.error.c_str());
    return 1;
  }
  if (cmd == "derive") return derive(loaded.map, argv[3], argv[4]);
  return cmd == "info" ? info(path, loaded.map) : heights(loaded.map, argv[3], scale);
}
