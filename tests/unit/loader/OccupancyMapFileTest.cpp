// Occupancy maps in map_server's format: P5 and P2 images, the vertical flip, trinary thresholds
// and negate as map_server reads them, the round trip with the costmap export, one message per
// kind of bad input (naming the YAML file and the key), and the shipped maps.
#include "loader/OccupancyMapFile.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <initializer_list>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "loader/CostmapExport.hpp"
#include "tests/unit/loader/MapFileTestUtil.hpp"

namespace carril::loader {
namespace {

namespace cost = fw::cost;
using test::fresh_dir;
using test::read_bytes;
using test::write_bytes;

constexpr std::size_t kMaxCells = 1000;
constexpr std::uint8_t F = cost::kFree, L = cost::kLethal, U = cost::kUnknown;

const std::string kYaml =
    "image: m.pgm\n"
    "resolution: 0.05\n"
    "origin: [-1.0, 2.5, 0.0]\n"
    "negate: 0\n"
    "occupied_thresh: 0.65\n"
    "free_thresh: 0.196\n"
    "mode: trinary\n";

// `text` with `from` (which must occur) replaced by `to`.
std::string edit(const std::string& text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos == std::string::npos) return text;
  std::string out = text;
  out.replace(pos, from.size(), to);
  return out;
}

// A 3 x 2 P5 image: top row (the map's upper row) white, grey 205, black; bottom row black,
// white, white.
std::string sample_p5() {
  return std::string("P5\n3 2\n255\n") + std::string("\xFF\xCD\x00\x00\xFF\xFF", 6);
}

// Writes the YAML (as `yaml`) and the image `pgm` as m.pgm in a fresh directory; the YAML's path.
std::string write_map(const std::string& pgm, const std::string& yaml = kYaml) {
  const auto dir = fresh_dir();
  write_bytes(dir / "m.pgm", pgm);
  write_bytes(dir / "m.yaml", yaml);
  return (dir / "m.yaml").string();
}

// Loads `yaml_path` and expects an error that begins with the YAML's path and contains every
// one of `parts`; the message.
std::string expect_error(const std::string& yaml_path, std::initializer_list<std::string> parts,
                         std::size_t max_cells = kMaxCells) {
  const OccupancyMapLoad r = load_occupancy_map(yaml_path, max_cells);
  EXPECT_FALSE(r.ok()) << yaml_path << " loaded";
  EXPECT_TRUE(r.map.cells.empty());
  EXPECT_EQ(r.error.rfind(yaml_path + ":", 0), 0U) << r.error;
  for (const std::string& p : parts) EXPECT_NE(r.error.find(p), std::string::npos) << r.error;
  return r.error;
}

OccupancyMapData load_ok(const std::string& yaml_path, std::size_t max_cells = kMaxCells) {
  OccupancyMapLoad r = load_occupancy_map(yaml_path, max_cells);
  EXPECT_TRUE(r.ok()) << r.error;
  return std::move(r.map);
}

// map_server's trinary reading (ROS 1 map_server and Nav2's map_io), as the reference.
std::uint8_t reference_trinary(int v, int maxval, bool negate, double occ, double free) {
  const double p = negate ? v / double(maxval) : (maxval - v) / double(maxval);
  return p > occ ? L : p < free ? F : U;
}

TEST(OccupancyMapFile, P5LoadsFlippedWithItsGeometry) {
  const std::string yaml = write_map(sample_p5());
  const OccupancyMapData m = load_ok(yaml);
  EXPECT_EQ(m.info.nx, 3);
  EXPECT_EQ(m.info.ny, 2);
  EXPECT_EQ(m.info.resolution_m, 0.05);
  EXPECT_EQ(m.info.origin_x_m, -1.0);
  EXPECT_EQ(m.info.origin_y_m, 2.5);
  EXPECT_EQ(m.image_path, (std::filesystem::path(yaml).parent_path() / "m.pgm").string());
  // Row j = 0 (lowest y) is the image's bottom row.
  EXPECT_EQ(m.cells, (std::vector<std::uint8_t>{L, F, F, F, U, L}));
  fw::OccupancyGrid grid(kMaxCells);
  ASSERT_TRUE(grid.assign(m.info, m.cells.data())) << grid.assign(m.info, m.cells.data()).message();
  EXPECT_EQ(grid.at(0, 1), F);  // top-left pixel
  EXPECT_EQ(grid.at(2, 1), L);  // top-right pixel
  EXPECT_EQ(grid.at(0, 0), L);  // bottom-left pixel
}

TEST(OccupancyMapFile, P2WithCommentsReadsLikeP5) {
  const std::string p2 =
      "P2\n# a comment\n3 # another\n2\n255\n"
      "255 205 0 # end of the top row\n"
      "0\n255 255\n";
  EXPECT_EQ(load_ok(write_map(p2)).cells, load_ok(write_map(sample_p5())).cells);
  // Comments in a P5 header too; the raster after one whitespace byte may hold '#' and spaces.
  const std::string p5 = std::string("P5 # binary\n2 1\n# maxval next\n255\n") + "# ";
  const OccupancyMapData m = load_ok(write_map(p5));
  EXPECT_EQ(m.cells, (std::vector<std::uint8_t>{L, L}));  // '#' 35 and ' ' 32 are dark
}

TEST(OccupancyMapFile, TrinaryThresholdsAsMapServer) {
  std::string pgm = "P5\n256 1\n255\n";
  for (int v = 0; v < 256; ++v) pgm += static_cast<char>(v);
  for (const bool negate : {false, true}) {
    for (const auto& [occ, free] : {std::pair{0.65, 0.196}, std::pair{0.6, 0.2}}) {
      const std::string yaml =
          edit(edit(edit(kYaml, "negate: 0", negate ? "negate: 1" : "negate: 0"),
                    "occupied_thresh: 0.65", "occupied_thresh: " + std::to_string(occ)),
               "free_thresh: 0.196", "free_thresh: " + std::to_string(free));
      const OccupancyMapData m = load_ok(write_map(pgm, yaml));
      ASSERT_EQ(m.cells.size(), 256U);
      for (int v = 0; v < 256; ++v) {
        EXPECT_EQ(m.cells[std::size_t(v)], reference_trinary(v, 255, negate, occ, free))
            << "grey " << v << " negate " << negate << " thresholds " << occ << "/" << free;
      }
    }
  }
  // Exactly at a threshold is neither side: unknown. 0.6 = (255 - 102) / 255, 0.2 = 51 / 255.
  const std::string at = std::string("P5\n2 1\n255\n") + static_cast<char>(102) + "\xCC";
  const std::string yaml = edit(edit(kYaml, "occupied_thresh: 0.65", "occupied_thresh: 0.6"),
                                "free_thresh: 0.196", "free_thresh: 0.2");
  EXPECT_EQ(load_ok(write_map(at, yaml)).cells, (std::vector<std::uint8_t>{U, U}));
}

TEST(OccupancyMapFile, NegateMakesBlackFree) {
  // p = v / 255 with negate: 0 free, 50 (p 0.196078) and 128 unknown, 255 occupied.
  const std::string p2 = "P2 4 1 255 0 50 128 255";
  EXPECT_EQ(load_ok(write_map(p2)).cells, (std::vector<std::uint8_t>{L, L, U, F}));
  EXPECT_EQ(load_ok(write_map(p2, edit(kYaml, "negate: 0", "negate: 1"))).cells,
            (std::vector<std::uint8_t>{F, U, U, L}));
}
TEST(OccupancyMapFile, MaxvalBelow255ScalesTheGreys) {
  // maxval 1: 0 black (occupied), 1 white (free); maxval 15: 5 is p = 10/15 > 0.65, 11 is
  // p = 4/15, unknown.
  EXPECT_EQ(load_ok(write_map("P2 2 1 1  0 1")).cells, (std::vector<std::uint8_t>{L, F}));
  const OccupancyMapData m = load_ok(write_map("P2 4 1 15 0 5 11 15"));
  const std::array<int, 4> greys = {0, 5, 11, 15};
  for (std::size_t i = 0; i < greys.size(); ++i) {
    EXPECT_EQ(m.cells[i], reference_trinary(greys[i], 15, false, 0.65, 0.196)) << greys[i];
  }
  EXPECT_EQ(m.cells, (std::vector<std::uint8_t>{L, L, U, F}));
}

TEST(OccupancyMapFile, ReadsWhatTheCostmapExportWrites) {
  // Every cost, 16 x 16, through export_costmap_pgm: passable reads free, inscribed and lethal
  // occupied, unknown unknown; geometry exact.
  std::array<std::uint8_t, 256> costs{};
  for (int c = 0; c < 256; ++c) costs[std::size_t(c)] = static_cast<std::uint8_t>(c);
  const auto dir = fresh_dir();
  const CostmapGeometry g{16, 16, 0.1, -3.25, 1.75};
  ASSERT_EQ(export_costmap_pgm((dir / "exported").string(), costs.data(), g), std::nullopt);
  const OccupancyMapData m = load_ok((dir / "exported.yaml").string());
  EXPECT_EQ(m.info.nx, 16);
  EXPECT_EQ(m.info.ny, 16);
  EXPECT_EQ(m.info.resolution_m, 0.1);
  EXPECT_EQ(m.info.origin_x_m, -3.25);
  EXPECT_EQ(m.info.origin_y_m, 1.75);
  ASSERT_EQ(m.cells.size(), 256U);
  for (int c = 0; c < 256; ++c) {
    const auto cc = static_cast<std::uint8_t>(c);
    const std::uint8_t want = cost::passable(cc) ? F : cc == cost::kUnknown ? U : L;
    EXPECT_EQ(m.cells[std::size_t(c)], want) << "cost " << c;
  }
}

TEST(OccupancyMapFile, SaveThenLoadIsExact) {
  OccupancyMapData m;
  m.info = {5, 3, 0.05, -0.75, 4.0};
  m.cells = {F, L, U, F, F, L, L, F, U, U, F, F, F, L, F};
  const auto dir = fresh_dir();
  ASSERT_EQ(save_occupancy_map((dir / "saved").string(), m), std::nullopt);
  const OccupancyMapData back = load_ok((dir / "saved.yaml").string());
  EXPECT_EQ(back.cells, m.cells);
  EXPECT_EQ(back.info.nx, 5);
  EXPECT_EQ(back.info.ny, 3);
  EXPECT_EQ(back.info.origin_x_m, -0.75);
  EXPECT_EQ(back.info.origin_y_m, 4.0);
  m.cells.pop_back();
  const auto err = save_occupancy_map((dir / "bad").string(), m);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("15 but the map has 14"), std::string::npos) << *err;
}

TEST(OccupancyMapFile, MissingYamlFile) {
  const std::string path = (fresh_dir() / "none.yaml").string();
  expect_error(path, {"cannot open"});
}

TEST(OccupancyMapFile, NotAPgm) {
  const std::string png = "\x89PNG\r\n\x1a\n" + std::string(16, '\0');
  const std::string yaml = write_map(png);
  const std::string pgm = (std::filesystem::path(yaml).parent_path() / "m.pgm").string();
  expect_error(yaml, {": image: " + pgm +
                      ": not a PGM image (it looks like a PNG file, expected the magic P5 or P2)"});
  expect_error(write_map("P6\n3 2\n255\n" + std::string(18, '\0')),
               {"image: ", "magic P6 is another netpbm type"});
  expect_error(write_map("P55 3 2 255\n"), {"image: ", "not a PGM image"});
  expect_error(write_map(""), {"image: ", "not a PGM image (an empty file"});
}

TEST(OccupancyMapFile, MissingImage) {
  const std::string yaml = write_map(sample_p5(), edit(kYaml, "m.pgm", "gone.pgm"));
  const std::string pgm = (std::filesystem::path(yaml).parent_path() / "gone.pgm").string();
  expect_error(yaml, {":1: image: " + pgm + ": not found"});
  // A directory is no image; an empty name no file.
  std::filesystem::create_directory(std::filesystem::path(yaml).parent_path() / "d.pgm");
  write_bytes(yaml, edit(kYaml, "m.pgm", "d.pgm"));
  expect_error(yaml, {"image: ", "d.pgm: not a regular file"});
  write_bytes(yaml, edit(kYaml, "m.pgm", "\"\""));
  expect_error(yaml, {"image: expected a file name, got an empty string"});
}

TEST(OccupancyMapFile, AbsoluteImagePath) {
  const std::string yaml = write_map(sample_p5());
  const auto abs = std::filesystem::path(yaml).parent_path() / "m.pgm";
  const auto other = std::filesystem::path(yaml).parent_path() / "sub" / "elsewhere.yaml";
  std::filesystem::create_directory(other.parent_path());
  write_bytes(other, edit(kYaml, "m.pgm", abs.string()));
  EXPECT_EQ(load_ok(other.string()).image_path, abs.string());
}

TEST(OccupancyMapFile, MissingKey) {
  for (const char* key :
       {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"}) {
    std::string yaml;
    for (std::size_t at = 0, next; at < kYaml.size(); at = next + 1) {
      next = kYaml.find('\n', at);
      const std::string line = kYaml.substr(at, next - at + 1);
      if (line.rfind(std::string(key) + ":", 0) != 0) yaml += line;
    }
    expect_error(write_map(sample_p5(), yaml), {std::string(key) + ": missing required key"});
  }
  // mode is optional (trinary).
  EXPECT_EQ(load_ok(write_map(sample_p5(), edit(kYaml, "mode: trinary\n", ""))).cells.size(), 6U);
}

TEST(OccupancyMapFile, UnknownKey) {
  expect_error(write_map(sample_p5(), kYaml + "frame: map\n"),
               {"frame: unknown key (allowed: image, resolution, origin"});
}

TEST(OccupancyMapFile, WrongType) {
  const std::string p = sample_p5();
  expect_error(write_map(p, edit(kYaml, "0.05", "\"0.05\"")),
               {":2: resolution: expected a number, got \"0.05\""});
  expect_error(write_map(p, edit(kYaml, "[-1.0, 2.5, 0.0]", "-1.0")), {"origin: expected a list"});
  expect_error(write_map(p, edit(kYaml, "[-1.0, 2.5, 0.0]", "[-1.0, 2.5]")),
               {"origin: expected [x, y, yaw] (3 numbers), got a list of 2"});
  expect_error(write_map(p, edit(kYaml, "negate: 0", "negate: true")),
               {"negate: expected an integer"});
  expect_error(write_map(p, edit(kYaml, "negate: 0", "negate: 2")),
               {"negate: expected an integer in [0, 1], got 2"});
  expect_error(write_map(p, edit(kYaml, "image: m.pgm", "image: [m.pgm]")),
               {"image: expected a string, got a list"});
  expect_error(write_map(p, "image: m.pgm\nresolution: [\n"), {"invalid YAML"});
  expect_error(write_map(p, "- image\n"), {"(top level): expected a map"});
}

TEST(OccupancyMapFile, ThresholdsOutOfRangeOrCrossed) {
  const std::string p = sample_p5();
  expect_error(write_map(p, edit(kYaml, "occupied_thresh: 0.65", "occupied_thresh: 1.5")),
               {"occupied_thresh: expected a number in [0, 1], got 1.5"});
  expect_error(write_map(p, edit(kYaml, "free_thresh: 0.196", "free_thresh: -0.1")),
               {"free_thresh: expected a number in [0, 1], got -0.1"});
  expect_error(write_map(p, edit(kYaml, "free_thresh: 0.196", "free_thresh: 0.65")),
               {"free_thresh: expected a number below occupied_thresh (0.65), got 0.65"});
}

TEST(OccupancyMapFile, ResolutionNotPositive) {
  for (const char* r : {"0", "-0.05"}) {
    expect_error(write_map(sample_p5(), edit(kYaml, "0.05", r)),
                 {"resolution: expected a number in (0, 100], got " + std::string(r)});
  }
}

TEST(OccupancyMapFile, RotatedOriginRefused) {
  expect_error(write_map(sample_p5(), edit(kYaml, "2.5, 0.0]", "2.5, 0.3]")),
               {"origin[2]: expected 0 (the yaw must be 0", "got 0.3"});
}

TEST(OccupancyMapFile, ScaleAndRawModesRefused) {
  for (const std::string mode : {"scale", "raw"}) {
    expect_error(write_map(sample_p5(), edit(kYaml, "mode: trinary", "mode: " + mode)),
                 {":7: mode: expected trinary", "map_server's " + mode + " mode is not supported",
                  "got \"" + mode + "\""});
  }
  expect_error(write_map(sample_p5(), edit(kYaml, "mode: trinary", "mode: binary")),
               {"mode: expected trinary, got \"binary\""});
}

TEST(OccupancyMapFile, BiggerThanTheBuffer) {
  const std::string yaml = write_map(sample_p5());
  expect_error(
      yaml, {"image: ", "m.pgm: 3 x 2 = 6 cells, more than the 5 cells the map buffer holds"}, 5);
  EXPECT_EQ(load_ok(yaml, 6).cells.size(), 6U);
  // A header alone is refused on its sizes, before any pixel is read or allocated.
  expect_error(write_map("P5 2000000 1 255\n"),
               {"2000000 x 1 pixels, a side may have at most 1048576"}, std::size_t(-1));
  expect_error(write_map("P5 100000 100000 255\n"), {"100000 x 100000 = 10000000000 cells"},
               std::size_t(-1) >> 40);
}

TEST(OccupancyMapFile, ImageFileTooBig) {
  const std::string yaml = write_map("P5 1 1 255\n\xFF");
  const auto pgm = std::filesystem::path(yaml).parent_path() / "m.pgm";
  std::filesystem::resize_file(pgm, kMaxMapImageBytes + 1);  // sparse: no disk used
  expect_error(yaml, {"m.pgm: 67108865 bytes, more than the 67108864 an image may have"},
               std::size_t(-1));
}

TEST(OccupancyMapFile, EmptyMap) {
  expect_error(write_map("P5\n0 4\n255\n"), {"image: ", "empty map: 0 x 4 pixels"});
  expect_error(write_map("P2 3 0 255\n"), {"empty map: 3 x 0 pixels"});
}

TEST(OccupancyMapFile, BadHeaders) {
  expect_error(write_map("P5\n3 x 255\n"), {"height: expected a decimal number, got 'x'"});
  expect_error(write_map("P5\n3 2\n"), {"truncated: the file ends before the maxval"});
  expect_error(write_map("P5\n3 2 0\n"), {"maxval 0, expected 1 to 255"});
  expect_error(write_map("P5\n3 2 65535\n" + std::string(12, '\0')),
               {"maxval 65535, expected 1 to 255 (8-bit greys; 16-bit PGMs are not supported)"});
  expect_error(write_map("P5\n3 2 255"), {"truncated: the file ends before the pixels"});
  expect_error(write_map("P5\n3 2 25a\n"), {"maxval: expected whitespace after the number"});
}

TEST(OccupancyMapFile, TruncatedOrTrailingP5) {
  const std::string p = sample_p5();
  expect_error(write_map(p.substr(0, p.size() - 1)),
               {"truncated: 3 x 2 pixels need 6 bytes after the header, the file has 5"});
  expect_error(write_map(p + "P5\n"),
               {"trailing bytes: 3 x 2 pixels need 6 bytes after the header, the file has 9"});
  expect_error(write_map("P5 3 2 200\n" + std::string(5, '\0') + "\xC9"),
               {"pixel (2, 1) is 201, above maxval 200"});
}

TEST(OccupancyMapFile, BadP2Pixels) {
  expect_error(write_map("P2 3 2 255\n255 205 0\n0 255\n"),
               {"truncated: the file ends before the pixel (2, 1)"});
  expect_error(write_map("P2 3 2 255\n255 205 0\n0 255 255 7\n"),
               {"trailing data after the 3 x 2 pixels"});
  expect_error(write_map("P2 3 2 255\n255 205 256\n0 255 255\n"),
               {"pixel (2, 0) is 256, above maxval 255"});
  expect_error(write_map("P2 3 2 255\n255 -5 0\n0 255 255\n"),
               {"pixel (1, 0): expected a decimal number, got '-'"});
}

// The shipped maps (scenarios/maps, tools/maps/make_maps.py) with the free start and goal points
// docs/map-formats.md lists: each point has no occupied or unknown cell within 0.45 m (half a
// 0.5 m wide robot plus 0.2 m).
struct Shipped {
  const char* name;
  int nx, ny;
  double resolution;
  std::vector<std::pair<double, double>> points;  // world (0, 0) first
};

TEST(OccupancyMapFile, ShippedMapsLoadAndFitTheStaticMap) {
  const std::vector<Shipped> maps = {
      {"house",
       210,
       170,
       0.05,
       {{0, 0}, {-3.8, 0}, {-2.6, -1.55}, {1.3, -2.05}, {-2.3, 1.4}, {0.25, 1.85}, {3.6, 1.4}}},
      {"warehouse",
       410,
       290,
       0.05,
       {{0, 0}, {7.0, -3.0}, {13.0, 3.0}, {16.0, 0.0}, {-1.0, -5.0}, {0.5, 4.0}}},
      {"city",
       250,
       250,
       0.1,
       {{0, 0}, {13.6, 13.6}, {-6.8, 6.8}, {3.4, -6.8}, {11.2, -4.4}, {3.4, 0.0}}},
  };
  for (const Shipped& s : maps) {
    SCOPED_TRACE(s.name);
    const std::string path = std::string(CARRIL_SOURCE_DIR) + "/scenarios/maps/" + s.name + ".yaml";
    const OccupancyMapData m = load_ok(path, 1'000'000);
    EXPECT_EQ(m.info.nx, s.nx);
    EXPECT_EQ(m.info.ny, s.ny);
    EXPECT_EQ(m.info.resolution_m, s.resolution);
    fw::OccupancyGrid grid(std::size_t(s.nx) * std::size_t(s.ny));
    const fw::Status st = grid.assign(m.info, m.cells.data());
    ASSERT_TRUE(st) << st.message();
    std::size_t occupied = 0, unknown = 0;
    for (std::uint8_t c : m.cells) {
      occupied += c == L ? 1 : 0;
      unknown += c == U ? 1 : 0;
    }
    EXPECT_GT(occupied, 0U);
    EXPECT_GT(unknown, 0U);  // the margin round the outer wall
    for (const auto& [x, y] : s.points) {
      int ci = 0, cj = 0;
      ASSERT_TRUE(grid.cell_of(x, y, ci, cj)) << x << ", " << y;
      const int reach = int(std::ceil(0.45 / s.resolution)) + 1;
      for (int j = cj - reach; j <= cj + reach; ++j) {
        for (int i = ci - reach; i <= ci + reach; ++i) {
          const fw::Vec2 c = grid.centre(i, j);
          // The nearest point of cell (i, j) to (x, y).
          const double h = s.resolution / 2;
          const double dx = std::max(std::abs(c.x() - x) - h, 0.0);
          const double dy = std::max(std::abs(c.y() - y) - h, 0.0);
          if (std::hypot(dx, dy) < 0.45) {
            EXPECT_TRUE(grid.is_free(i, j)) << "(" << x << ", " << y << "): cell " << i << ", " << j
                                            << " is " << int(grid.at(i, j));
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace carril::loader
