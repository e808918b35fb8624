#include "loader/CostmapExport.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "firmware/mapping/CostValues.hpp"
#include "loader/AtomicWrite.hpp"
#include "loader/SafeCreate.hpp"

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

// Whether the YAML at `yaml_path` (one this exporter wrote) names `image` as its image.
bool current_image_is(const std::string& yaml_path, const std::string& image) {
  std::ifstream in(yaml_path);
  std::string line;
  const std::string want = "image: " + yaml_quoted(image);
  while (std::getline(in, line)) {
    if (line == want) return true;
  }
  return false;
}

// Temporaries of an export that was killed (".BASE.pgm.tmp.*" and the like), ours only.
void remove_stale_temporaries(const std::string& base_path) {
  const std::filesystem::path base(base_path);
  const std::filesystem::path dir = base.has_parent_path() ? base.parent_path() : ".";
  const std::string prefix = "." + base.filename().string() + ".";
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.find(".tmp.") == std::string::npos) continue;
    std::string why;
    clear_stale_output(e.path().string(), why);  // a regular file of ours, or left alone
  }
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

std::optional<std::string> write_costmap_image(const std::string& base_path,
                                               const std::uint8_t* costs, const CostmapGeometry& g,
                                               CostmapImageStep& step) {
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
  // The pair switches at one atomic step, the YAML's rename: the new image goes under the name
  // the current YAML does not use (BASE.pgm and BASE.next.pgm alternate), so a kill before the
  // YAML leaves the old pair whole, and one after leaves the new pair; the old image goes last.
  const std::string next_path = base_path + ".next.pgm";
  const std::string next_name = std::filesystem::path(next_path).filename().string();
  const bool old_uses_next = current_image_is(yaml_path, next_name);
  step.had_yaml = std::filesystem::exists(yaml_path);
  step.old_image_path = old_uses_next ? next_path : pgm_path;
  // With no YAML yet there is no old pair to keep: the image takes the plain name.
  step.image_path = !step.had_yaml ? pgm_path : old_uses_next ? pgm_path : next_path;
  remove_stale_temporaries(base_path);
  return write_file_atomically(step.image_path, pgm);
}

std::optional<std::string> commit_costmap_yaml(const std::string& base_path,
                                               const CostmapGeometry& g,
                                               const CostmapImageStep& step) {
  // map_server resolves `image` relative to the YAML file.
  const std::string image = std::filesystem::path(step.image_path).filename().string();
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
  if (auto err = write_file_atomically(base_path + ".yaml", yaml)) return err;
  if (step.had_yaml && step.old_image_path != step.image_path) {
    std::error_code ec;
    std::filesystem::remove(step.old_image_path, ec);  // the old pair's image; absent is fine
  }
  return std::nullopt;
}

std::optional<std::string> export_costmap_pgm(const std::string& base_path,
                                              const std::uint8_t* costs, const CostmapGeometry& g) {
  CostmapImageStep step;
  if (auto err = write_costmap_image(base_path, costs, g, step)) return err;
  return commit_costmap_yaml(base_path, g, step);
}

}  // namespace carril::loader
