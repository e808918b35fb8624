#include "loader/CostmapPng.hpp"

#include <cmath>
#include <cstdlib>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "loader/AtomicWrite.hpp"
#include "loader/PngEncode.hpp"

namespace carril::loader {

namespace {

namespace cost = fw::cost;

constexpr int kMaxScale = 16;
// Beyond this the image is no documentation figure any more (and libpng needs it in memory).
constexpr std::size_t kMaxPixels = std::size_t{1} << 28;

constexpr std::array<std::uint8_t, 3> kFree = {255, 255, 255};
constexpr std::array<std::uint8_t, 3> kGradedLow = {255, 245, 170};  // light yellow
constexpr std::array<std::uint8_t, 3> kGradedHigh = {205, 110, 0};   // dark orange
constexpr std::array<std::uint8_t, 3> kInscribed = {255, 90, 0};     // orange-red
constexpr std::array<std::uint8_t, 3> kLethal = {0, 0, 0};
constexpr std::array<std::uint8_t, 3> kUnknown = {128, 128, 128};

}  // namespace

std::array<std::uint8_t, 3> costmap_png_rgb(std::uint8_t c) {
  if (c == cost::kFree) return kFree;
  if (c <= cost::kMaxGraded) {
    std::array<std::uint8_t, 3> out{};
    for (std::size_t k = 0; k < 3; ++k) {
      const int lo = kGradedLow[k];
      const int hi = kGradedHigh[k];
      // Linear from kGradedLow at cost 1 to kGradedHigh at cost 252, rounded.
      const double t = (c - 1) / static_cast<double>(cost::kMaxGraded - 1);
      const long v = std::lround(lo + (hi - lo) * t);
      out[k] = static_cast<std::uint8_t>(v);
    }
    return out;
  }
  if (c == cost::kInscribed) return kInscribed;
  if (c == cost::kLethal) return kLethal;
  return kUnknown;
}

std::optional<std::string> export_costmap_png(const std::string& path, const std::uint8_t* costs,
                                              const CostmapGeometry& g, int scale) {
  if (costs == nullptr || g.nx == 0 || g.ny == 0) {
    return path + ": nothing to export (no costs, or nx " + std::to_string(g.nx) + ", ny " +
           std::to_string(g.ny) + ")";
  }
  if (scale < 1 || scale > kMaxScale) {
    return path + ": scale must be 1 to " + std::to_string(kMaxScale) + ", got " +
           std::to_string(scale);
  }
  const auto s = static_cast<std::size_t>(scale);
  const std::size_t width = g.nx * s;
  const std::size_t height = g.ny * s;
  if (width * height > kMaxPixels) {
    return path + ": image too big: " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels (at most " + std::to_string(kMaxPixels) + ")";
  }
  std::vector<std::uint8_t> rgb(width * height * 3);
  for (std::size_t y = 0; y < height; ++y) {
    const std::size_t row = g.ny - 1 - y / s;  // top of the image = highest y
    std::uint8_t* dst = rgb.data() + y * width * 3;
    for (std::size_t x = 0; x < width; ++x) {
      const auto c = costmap_png_rgb(costs[row * g.nx + x / s]);
      dst[3 * x] = c[0];
      dst[3 * x + 1] = c[1];
      dst[3 * x + 2] = c[2];
    }
  }
  std::string bytes;
  if (auto err = encode_png(rgb.data(), int(width), int(height), PngPixels::Rgb, 0, bytes)) {
    return path + ": " + *err;
  }
  return write_file_atomically(path, bytes);
}

}  // namespace carril::loader
