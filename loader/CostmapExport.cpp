#include "loader/CostmapExport.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "firmware/mapping/CostValues.hpp"
#include "loader/AtomicWrite.hpp"

namespace carril::loader {

namespace {

namespace cost = fw::cost;

// map_server's thresholds on the occupancy p = (255 - grey) / 255: free below 0.196 (grey >= 206),
// occupied above 0.65 (grey <= 89), unknown between (205 is the conventional unknown grey).
constexpr std::uint8_t kGreyFree = 254;
constexpr std::uint8_t kGreyGradedLightest = 253;
constexpr std::uint8_t kGreyGradedDarkest = 206;
constexpr std::uint8_t kGreyUnknown = 205;
constexpr std::uint8_t kGreyOccupied = 0;

// Shortest text that reads back as the same double.
std::string shortest(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

// A YAML double-quoted scalar (file names may hold ':' or '#').
std::string yaml_quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::uint8_t costmap_pgm_grey(std::uint8_t c) {
  if (c == cost::kFree) return kGreyFree;
  if (c <= cost::kMaxGraded) {
    // 1 -> 253 ... 252 -> 206: darker for costlier, never crossing into map_server's unknown band.
    constexpr int kSpan = kGreyGradedLightest - kGreyGradedDarkest;  // 47
    const int step = ((c - 1) * kSpan + (cost::kMaxGraded - 1) / 2) / (cost::kMaxGraded - 1);
    return static_cast<std::uint8_t>(kGreyGradedLightest - step);
  }
  if (c == cost::kUnknown) return kGreyUnknown;
  return kGreyOccupied;  // inscribed, lethal
}

std::optional<std::string> export_costmap_pgm(const std::string& base_path,
                                              const std::uint8_t* costs, const CostmapGeometry& g) {
  const std::string pgm_path = base_path + ".pgm";
  const std::string yaml_path = base_path + ".yaml";
  if (costs == nullptr || g.nx == 0 || g.ny == 0) {
    return pgm_path + ": nothing to export (no costs, or nx " + std::to_string(g.nx) + ", ny " +
           std::to_string(g.ny) + ")";
  }
  if (!std::isfinite(g.resolution_m) || !(g.resolution_m > 0.0) || !std::isfinite(g.origin_x_m) ||
      !std::isfinite(g.origin_y_m)) {
    return yaml_path + ": resolution must be finite and > 0 and the origin finite, got " +
           shortest(g.resolution_m) + " at (" + shortest(g.origin_x_m) + ", " +
           shortest(g.origin_y_m) + ")";
  }
  std::string pgm = "P5\n" + std::to_string(g.nx) + " " + std::to_string(g.ny) + "\n255\n";
  const std::size_t header = pgm.size();
  const std::size_t nx = g.nx;
  pgm.resize(header + nx * g.ny);
  // Image rows go top (highest y) to bottom; the costs' rows go up from the lowest y.
  for (std::size_t row = 0; row < g.ny; ++row) {
    const std::uint8_t* src = costs + (g.ny - 1 - row) * nx;
    char* dst = pgm.data() + header + row * nx;
    for (std::size_t i = 0; i < nx; ++i) dst[i] = static_cast<char>(costmap_pgm_grey(src[i]));
  }
  if (auto err = write_file_atomically(pgm_path, pgm)) return err;
  // map_server resolves `image` relative to the YAML file.
  const std::string image = std::filesystem::path(pgm_path).filename().string();
  const std::string yaml =
      "# carril costmap (docs/map-formats.md): trinary, so unknown cells stay unknown;\n"
      "# graded costs are greys that read as free.\n"
      "image: " +
      yaml_quoted(image) + "\n" +
      "mode: trinary\n"
      "resolution: " +
      shortest(g.resolution_m) + "\n" + "origin: [" + shortest(g.origin_x_m) + ", " +
      shortest(g.origin_y_m) + ", 0.0]\n" +
      "negate: 0\n"
      "occupied_thresh: 0.65\n"
      "free_thresh: 0.196\n";
  return write_file_atomically(yaml_path, yaml);
}

}  // namespace carril::loader
