#include "loader/OccupancyMapFile.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "firmware/mapping/CostValues.hpp"
#include "loader/CostmapExport.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::loader {

namespace {

namespace cost = fw::cost;
using strict::Node;
using strict::Range;

// A fault inside the image; the caller prefixes the YAML file, the key and the image's path.
class PgmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The header of a PGM (netpbm "P5" binary or "P2" plain): sizes, maxval, where the pixels start.
struct PgmHeader {
  bool binary = true;
  std::uint64_t width = 0, height = 0;
  std::uint32_t maxval = 0;
  std::size_t raster_at = 0;  // offset of the first pixel
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// A byte for a message: 'x' when printable, else its hex code.
std::string describe_byte(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x20 && u < 0x7F) return std::string("'") + c + "'";
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", u);
  return buf;
}

// What a file that is not a PGM looks like, by its magic: "a PNG file", "an empty file".
std::string kind_of(std::string_view b) {
  auto starts = [&](std::string_view m) { return b.substr(0, m.size()) == m; };
  if (b.empty()) return "an empty file";
  if (starts("\x89PNG")) return "it looks like a PNG file";
  if (starts("GIF8")) return "it looks like a GIF file";
  if (starts("\xFF\xD8\xFF")) return "it looks like a JPEG file";
  if (starts("BM")) return "it looks like a BMP file";
  return "it does not start with P5 or P2";
}

// Netpbm's tokens: decimal numbers separated by whitespace, '#' comments to the end of a line.
class PgmScanner {
 public:
  explicit PgmScanner(std::string_view bytes, std::size_t at) : b_(bytes), at_(at) {}

  std::size_t at() const { return at_; }
  bool at_end() const { return at_ >= b_.size(); }

  void skip_space_and_comments() {
    while (at_ < b_.size()) {
      if (is_space(b_[at_])) {
        ++at_;
      } else if (b_[at_] == '#') {
        while (at_ < b_.size() && b_[at_] != '\n' && b_[at_] != '\r') ++at_;
      } else {
        return;
      }
    }
  }

  // The next number; `what` names it in messages ("width", "pixel (3, 0)").
  std::uint64_t number(const std::string& what) {
    skip_space_and_comments();
    if (at_end()) throw PgmError("truncated: the file ends before the " + what);
    if (b_[at_] < '0' || b_[at_] > '9') {
      throw PgmError(what + ": expected a decimal number, got " + describe_byte(b_[at_]));
    }
    std::uint64_t v = 0;
    constexpr std::uint64_t kCap = 1'000'000'000'000ULL;  // far above any accepted value
    while (at_ < b_.size() && b_[at_] >= '0' && b_[at_] <= '9') {
      if (v < kCap) v = v * 10 + static_cast<std::uint64_t>(b_[at_] - '0');
      ++at_;
    }
    if (at_ < b_.size() && !is_space(b_[at_]) && b_[at_] != '#') {
      throw PgmError(what + ": expected whitespace after the number, got " +
                     describe_byte(b_[at_]));
    }
    return v;
  }

 private:
  std::string_view b_;
  std::size_t at_;
};

PgmHeader read_pgm_header(std::string_view b) {
  if (b.size() < 2 || b[0] != 'P' || (b.size() > 2 && !is_space(b[2]) && b[2] != '#')) {
    // What it is, when that is known; never its bytes (it may be any file on the machine).
    throw PgmError("not a PGM image (" + kind_of(b) + ", expected the magic P5 or P2)");
  }
  PgmHeader h;
  if (b[1] == '5') {
    h.binary = true;
  } else if (b[1] == '2') {
    h.binary = false;
  } else if (b[1] == '1' || b[1] == '3' || b[1] == '4' || b[1] == '6' || b[1] == '7') {
    throw PgmError(std::string("not a PGM image (magic P") + b[1] +
                   " is another netpbm type: bitmap, colour or PAM), expected a greyscale PGM "
                   "(P5 or P2)");
  } else {
    throw PgmError("not a PGM image (a 'P' without the 5 or 2 of the PGM magic)");
  }
  PgmScanner s(b, 2);
  h.width = s.number("width");
  h.height = s.number("height");
  const std::uint64_t maxval = s.number("maxval");
  if (maxval < 1 || maxval > 255) {
    throw PgmError("maxval " + std::to_string(maxval) +
                   ", expected 1 to 255 (8-bit greys; 16-bit PGMs are not supported)");
  }
  h.maxval = static_cast<std::uint32_t>(maxval);
  if (h.binary) {
    // Exactly one whitespace byte separates maxval from the pixels, which may themselves be
    // whitespace or '#' bytes.
    if (s.at() >= b.size()) throw PgmError("truncated: the file ends before the pixels");
    if (!is_space(b[s.at()])) {
      throw PgmError("expected one whitespace byte after maxval, got " + describe_byte(b[s.at()]));
    }
    h.raster_at = s.at() + 1;
  } else {
    h.raster_at = s.at();
  }
  return h;
}

// map_server's trinary reading of each grey 0..maxval.
std::array<std::uint8_t, 256> trinary_table(std::uint32_t maxval, bool negate, double occupied,
                                            double free) {
  std::array<std::uint8_t, 256> t{};
  for (std::uint32_t v = 0; v <= maxval; ++v) {
    // An exact integer numerator, as ROS 1's map_server: (255 - v) / 255.0.
    const double p = static_cast<double>(negate ? v : maxval - v) / static_cast<double>(maxval);
    t[v] = p > occupied ? cost::kLethal : p < free ? cost::kFree : cost::kUnknown;
  }
  return t;
}

// Fills `cells` (lower-left cell first) from the image rows (top row first).
void read_pgm_pixels(std::string_view b, const PgmHeader& h,
                     const std::array<std::uint8_t, 256>& table, std::vector<std::uint8_t>& cells) {
  const std::size_t w = h.width, rows = h.height, n = w * rows;
  cells.resize(n);
  if (h.binary) {
    const std::size_t got = b.size() - std::min(b.size(), h.raster_at);
    if (got != n) {
      throw PgmError(std::string(got < n ? "truncated" : "trailing bytes") + ": " +
                     std::to_string(w) + " x " + std::to_string(rows) + " pixels need " +
                     std::to_string(n) + " bytes after the header, the file has " +
                     std::to_string(got));
    }
    for (std::size_t r = 0; r < rows; ++r) {
      const auto* src = reinterpret_cast<const unsigned char*>(b.data() + h.raster_at + r * w);
      std::uint8_t* dst = cells.data() + (rows - 1 - r) * w;
      for (std::size_t i = 0; i < w; ++i) {
        if (src[i] > h.maxval) {
          throw PgmError("pixel (" + std::to_string(i) + ", " + std::to_string(r) + ") is " +
                         std::to_string(src[i]) + ", above maxval " + std::to_string(h.maxval));
        }
        dst[i] = table[src[i]];
      }
    }
    return;
  }
  PgmScanner s(b, h.raster_at);
  for (std::size_t r = 0; r < rows; ++r) {
    std::uint8_t* dst = cells.data() + (rows - 1 - r) * w;
    for (std::size_t i = 0; i < w; ++i) {
      const std::string name = "pixel (" + std::to_string(i) + ", " + std::to_string(r) + ")";
      const std::uint64_t v = s.number(name);
      if (v > h.maxval) {
        throw PgmError(name + " is " + std::to_string(v) + ", above maxval " +
                       std::to_string(h.maxval));
      }
      dst[i] = table[v];
    }
  }
  s.skip_space_and_comments();
  if (!s.at_end()) {
    throw PgmError("trailing data after the " + std::to_string(w) + " x " + std::to_string(rows) +
                   " pixels (at byte " + std::to_string(s.at()) + ")");
  }
}

// The whole image file, refusing anything but a regular file of at most kMaxMapImageBytes.
std::string read_image(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw PgmError("not found");
  if (!fs::is_regular_file(st)) throw PgmError("not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw PgmError("cannot read its size: " + ec.message());
  if (size > kMaxMapImageBytes) {
    throw PgmError(std::to_string(size) + " bytes, more than the " +
                   std::to_string(kMaxMapImageBytes) + " an image may have");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PgmError("cannot open");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) throw PgmError("cannot read");
  return bytes;
}

OccupancyMapData read_map(const std::string& yaml_path, std::size_t max_cells) {
  const std::string text = strict::read_file(yaml_path);
  const Node root = strict::parse_document(text, &yaml_path);
  root.expect_map(
      {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"});
  const Node image = root.at("image");
  const std::string image_name = image.string();
  if (image_name.empty()) image.expected("a file name", "an empty string");
  if (auto m = root.get("mode")) {
    const std::string mode = m->string();
    if (mode == "scale" || mode == "raw") {
      m->expected("trinary (cells are free, occupied or unknown; map_server's " + mode +
                      " mode is not supported)",
                  "\"" + mode + "\"");
    }
    m->one_of({"trinary"});
  }
  OccupancyMapData map;
  map.info.resolution_m = root.at("resolution").number(Range::open_closed(0.0, 100.0));
  const Node origin = root.at("origin");
  const auto xyz = origin.items();
  if (xyz.size() != 3) {
    origin.expected("[x, y, yaw] (3 numbers)", "a list of " + std::to_string(xyz.size()));
  }
  const Range coord = Range::closed(-1.0e6, 1.0e6);
  map.info.origin_x_m = xyz[0].number(coord);
  map.info.origin_y_m = xyz[1].number(coord);
  if (xyz[2].number() != 0.0) {
    xyz[2].expected("0 (the yaw must be 0: a rotated map is not supported)", xyz[2].raw());
  }
  const bool negate = root.at("negate").integer(0, 1) == 1;
  const double occupied = root.at("occupied_thresh").number(Range::closed(0.0, 1.0));
  const Node free_n = root.at("free_thresh");
  const double free = free_n.number(Range::closed(0.0, 1.0));
  if (!(free < occupied)) {
    free_n.expected("a number below occupied_thresh (" + strict::format_number(occupied) + ")",
                    free_n.raw());
  }

  namespace fs = std::filesystem;
  map.image_path = (fs::path(yaml_path).parent_path() / image_name).string();
  try {
    const std::string bytes = read_image(map.image_path);
    const PgmHeader h = read_pgm_header(bytes);
    const std::string size = std::to_string(h.width) + " x " + std::to_string(h.height);
    if (h.width == 0 || h.height == 0) throw PgmError("empty map: " + size + " pixels");
    if (h.width > kMaxMapImageSide || h.height > kMaxMapImageSide) {
      throw PgmError(size + " pixels, a side may have at most " + std::to_string(kMaxMapImageSide));
    }
    const std::uint64_t n = h.width * h.height;
    if (n > max_cells) {
      throw PgmError(size + " = " + std::to_string(n) + " cells, more than the " +
                     std::to_string(max_cells) + " cells the map buffer holds");
    }
    read_pgm_pixels(bytes, h, trinary_table(h.maxval, negate, occupied, free), map.cells);
    map.info.nx = static_cast<int>(h.width);
    map.info.ny = static_cast<int>(h.height);
  } catch (const PgmError& e) {
    image.fail(map.image_path + ": " + e.what());
  }
  if (const fw::Status s = map.info.validate(); !s) root.fail(s.message());
  return map;
}

}  // namespace

OccupancyMapLoad load_occupancy_map(const std::string& yaml_path, std::size_t max_cells) {
  OccupancyMapLoad r;
  if (!strict::guarded(yaml_path, r.error, [&] { r.map = read_map(yaml_path, max_cells); })) {
    r.map = OccupancyMapData{};
  }
  return r;
}

std::optional<std::string> save_occupancy_map(const std::string& base_path,
                                              const OccupancyMapData& map) {
  const fw::MapInfo& in = map.info;
  if (const fw::Status s = in.validate(); !s) return base_path + ".yaml: " + s.message();
  const std::size_t n = static_cast<std::size_t>(in.nx) * static_cast<std::size_t>(in.ny);
  if (map.cells.size() != n) {
    return base_path + ".pgm: nx * ny = " + std::to_string(n) + " but the map has " +
           std::to_string(map.cells.size()) + " cells";
  }
  const CostmapGeometry g{static_cast<std::uint32_t>(in.nx), static_cast<std::uint32_t>(in.ny),
                          in.resolution_m, in.origin_x_m, in.origin_y_m};
  return export_costmap_pgm(base_path, map.cells.data(), g);
}

}  // namespace carril::loader
