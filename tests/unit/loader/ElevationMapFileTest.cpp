// Saved elevation maps: byte layout, round trip, and one message per kind of bad file.
#include "loader/ElevationMapFile.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "tests/unit/loader/MapFileTestUtil.hpp"

namespace carril::loader {
namespace {

using test::fresh_dir;
using test::list_dir;
using test::read_bytes;
using test::write_bytes;

constexpr std::uint64_t kMaxCells = 1000;
constexpr std::size_t kOffVersion = 8, kOffResolution = 12, kOffNx = 20, kOffNy = 24,
                      kOffOriginX = 28, kOffOriginY = 36, kOffFrame = 44, kOffCellCount = 76;

// 7 x 5 cells: observed ones with distinct heights and variances, a few never observed.
ElevationMapData sample_map() {
  ElevationMapData m;
  m.resolution_m = 0.05;
  m.nx = 7;
  m.ny = 5;
  m.origin_x_m = -1.25;
  m.origin_y_m = 3.5;
  m.frame = "odom";
  m.cells.resize(35);
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    m.cells[i].height_m = static_cast<float>(i) * 0.01F - 0.1F;
    m.cells[i].variance_m2 = i % 4 == 3 ? 0.0F : 1e-4F * static_cast<float>(i + 1);
  }
  return m;
}

void put_u32(std::string& b, std::size_t off, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) b[off + i] = static_cast<char>((v >> (8 * i)) & 0xFFU);
}
void put_u64(std::string& b, std::size_t off, std::uint64_t v) {
  for (std::size_t i = 0; i < 8; ++i) b[off + i] = static_cast<char>((v >> (8 * i)) & 0xFFU);
}
std::uint32_t get_u32(const std::string& b, std::size_t off) {
  std::uint32_t v = 0;
  for (std::size_t i = 4; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(b[off + i]);
  return v;
}
std::uint64_t get_u64(const std::string& b, std::size_t off) {
  std::uint64_t v = 0;
  for (std::size_t i = 8; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(b[off + i]);
  return v;
}
// Recomputes the trailing CRC after an edit, so the check under test is the one that fires.
void fix_crc(std::string& b) {
  put_u32(b, b.size() - 4, crc32_ieee(b.data(), b.size() - 4));
}

// Saves the sample map in a fresh directory; the path.
std::string saved_sample() {
  const std::string path = (fresh_dir() / "site.cem").string();
  EXPECT_EQ(save_elevation_map(path, sample_map()), std::nullopt);
  return path;
}

std::string load_error(const std::string& path, std::uint64_t max_cells = kMaxCells) {
  const ElevationMapLoad r = load_elevation_map(path, max_cells);
  EXPECT_FALSE(r.ok()) << path << " loaded";
  EXPECT_TRUE(r.map.cells.empty());
  return r.error;
}

TEST(ElevationMapFile, Crc32IsTheIeeeOne) {
  // The standard check value of CRC-32/ISO-HDLC (zlib, PNG, Ethernet).
  EXPECT_EQ(crc32_ieee("123456789", 9), 0xCBF43926U);
  // Continuing over two pieces gives the CRC of the whole.
  EXPECT_EQ(crc32_ieee("6789", 4, crc32_ieee("12345", 5)), 0xCBF43926U);
  EXPECT_EQ(crc32_ieee("", 0), 0U);
  // Longer than the 8-byte steps, with a tail (zlib: crc32 of this sentence).
  const char* fox = "The quick brown fox jumps over the lazy dog";
  EXPECT_EQ(crc32_ieee(fox, std::strlen(fox)), 0x414FA339U);
}

TEST(ElevationMapFile, LayoutIsLittleEndianFieldByField) {
  const ElevationMapData m = sample_map();
  const std::string b = read_bytes(saved_sample());
  ASSERT_EQ(b.size(), 84U + 35U * 8U + 4U);
  EXPECT_EQ(b.substr(0, 8), "CARRILEM");
  EXPECT_EQ(b.substr(kOffVersion, 4), std::string("\x01\x00\x00\x00", 4));
  EXPECT_EQ(get_u64(b, kOffResolution), std::bit_cast<std::uint64_t>(0.05));
  EXPECT_EQ(get_u32(b, kOffNx), 7U);
  EXPECT_EQ(get_u32(b, kOffNy), 5U);
  EXPECT_EQ(get_u64(b, kOffOriginX), std::bit_cast<std::uint64_t>(-1.25));
  EXPECT_EQ(get_u64(b, kOffOriginY), std::bit_cast<std::uint64_t>(3.5));
  EXPECT_EQ(b.substr(kOffFrame, 32), std::string("odom") + std::string(28, '\0'));
  EXPECT_EQ(get_u64(b, kOffCellCount), 35U);
  // Cell (1, 2) = index 15, row-major from the lower-left cell: height then variance.
  EXPECT_EQ(get_u32(b, 84 + 15 * 8), std::bit_cast<std::uint32_t>(m.cells[15].height_m));
  EXPECT_EQ(get_u32(b, 84 + 15 * 8 + 4), std::bit_cast<std::uint32_t>(m.cells[15].variance_m2));
  EXPECT_EQ(get_u32(b, b.size() - 4), crc32_ieee(b.data(), b.size() - 4));
}

TEST(ElevationMapFile, RoundTripIsExact) {
  const ElevationMapData m = sample_map();
  const auto dir = fresh_dir();
  const std::string path = (dir / "site.cem").string();
  ASSERT_EQ(save_elevation_map(path, m), std::nullopt);
  EXPECT_EQ(list_dir(dir), std::vector<std::string>{"site.cem"});  // no temporary file left
  const ElevationMapLoad r = load_elevation_map(path, kMaxCells);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.map.resolution_m, m.resolution_m);
  EXPECT_EQ(r.map.nx, m.nx);
  EXPECT_EQ(r.map.ny, m.ny);
  EXPECT_EQ(r.map.origin_x_m, m.origin_x_m);
  EXPECT_EQ(r.map.origin_y_m, m.origin_y_m);
  EXPECT_EQ(r.map.frame, m.frame);
  ASSERT_EQ(r.map.cells.size(), m.cells.size());
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    EXPECT_EQ(r.map.cells[i].height_m, m.cells[i].height_m) << i;
    EXPECT_EQ(r.map.cells[i].variance_m2, m.cells[i].variance_m2) << i;
  }
  // Exactly as many cells as the grid holds is fine.
  EXPECT_TRUE(load_elevation_map(path, 35).ok());
}

TEST(ElevationMapFile, MissingFile) {
  const std::string path = (fresh_dir() / "nothing.cem").string();
  EXPECT_EQ(load_error(path), path + ": not found");
}

TEST(ElevationMapFile, TruncatedFile) {
  const std::string path = saved_sample();
  const std::string b = read_bytes(path);
  write_bytes(path, b.substr(0, b.size() - 5));
  EXPECT_EQ(load_error(path), path + ": truncated: expected 368 bytes for 7 x 5 cells, got 363");
  write_bytes(path, b.substr(0, 40));
  EXPECT_EQ(load_error(path),
            path + ": truncated: expected at least 88 bytes (header and CRC), got 40");
  write_bytes(path, b.substr(0, 4));
  EXPECT_EQ(load_error(path), path + ": truncated: expected at least 88 bytes, got 4");
  write_bytes(path, b + "extra");
  EXPECT_EQ(load_error(path),
            path + ": trailing bytes: expected 368 bytes for 7 x 5 cells, got 373");
}

TEST(ElevationMapFile, NotACarrilMap) {
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  b[0] = 'X';
  write_bytes(path, b);
  EXPECT_EQ(load_error(path),
            path + ": not a carril elevation map (the first 8 bytes are not \"CARRILEM\")");
  write_bytes(path, "P5\n3 2\n255\n");
  EXPECT_EQ(load_error(path),
            path + ": not a carril elevation map (the first 8 bytes are not \"CARRILEM\")");
}

TEST(ElevationMapFile, FlippedByteIsACrcMismatch) {
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  b[84 + 8 * 20 + 2] = static_cast<char>(b[84 + 8 * 20 + 2] ^ 0x10);
  write_bytes(path, b);
  const std::string error = load_error(path);
  EXPECT_EQ(error.rfind(path + ": CRC mismatch (corrupted): stored 0x", 0), 0U) << error;
}

TEST(ElevationMapFile, OtherVersionIsNamed) {
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  put_u32(b, kOffVersion, 7);
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path),
            path + ": unsupported format version: the file says 7, this build reads 1");
}

TEST(ElevationMapFile, TooBigForTheGrid) {
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  put_u32(b, kOffNx, 100000);
  put_u32(b, kOffNy, 100000);
  put_u64(b, kOffCellCount, 10000000000ULL);
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path),
            path +
                ": too big for the configured grid: 100000 x 100000 = 10000000000 cells, the "
                "grid holds 1000");
  // The genuine file, against a smaller grid.
  const std::string small = saved_sample();
  EXPECT_EQ(load_error(small, 34),
            small + ": too big for the configured grid: 7 x 5 = 35 cells, the grid holds 34");
}

TEST(ElevationMapFile, InconsistentSizes) {
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  put_u64(b, kOffCellCount, 36);
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path), path +
                                  ": inconsistent sizes: nx 7 * ny 5 = 35 cells, but the "
                                  "header's cell count is 36");
}

TEST(ElevationMapFile, NonFiniteNumbersAreRejected) {
  const std::string path = saved_sample();
  const std::string good = read_bytes(path);
  std::string b = good;
  put_u64(b, kOffResolution,
          std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN()));
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path), path + ": resolution must be a finite number > 0, got nan");
  b = good;
  put_u64(b, kOffOriginY, std::bit_cast<std::uint64_t>(-std::numeric_limits<double>::infinity()));
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path), path + ": origin must be finite, got (-1.25, -inf)");
  b = good;
  put_u32(b, 84 + 9 * 8 + 4, std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity()));
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path), path + ": cell (2, 1): variance must be finite and >= 0, got inf");
  b = good;
  put_u32(b, 84 + 9 * 8, std::bit_cast<std::uint32_t>(std::numeric_limits<float>::quiet_NaN()));
  fix_crc(b);
  write_bytes(path, b);
  EXPECT_EQ(load_error(path), path + ": cell (2, 1): observed cell with a non-finite height nan");
}

TEST(ElevationMapFile, UnobservedNanHeightLoadsAsZero) {
  // Another writer may mark "no height" with NaN; the cell is unobserved, so it means nothing.
  const std::string path = saved_sample();
  std::string b = read_bytes(path);
  put_u32(b, 84 + 3 * 8, std::bit_cast<std::uint32_t>(std::numeric_limits<float>::quiet_NaN()));
  fix_crc(b);
  write_bytes(path, b);
  const ElevationMapLoad r = load_elevation_map(path, kMaxCells);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_FALSE(r.map.cells[3].observed());
  EXPECT_EQ(r.map.cells[3].height_m, 0.0F);
}

TEST(ElevationMapFile, InvalidMapIsNotSaved) {
  const auto dir = fresh_dir();
  const std::string path = (dir / "bad.cem").string();
  ElevationMapData m = sample_map();
  m.cells.pop_back();
  EXPECT_EQ(save_elevation_map(path, m),
            path + ": cannot save the elevation map: nx * ny = 35 but the map has 34 cells");
  m = sample_map();
  m.frame = std::string(32, 'f');
  EXPECT_EQ(save_elevation_map(path, m).value_or("").find("frame name must be 1 to 31"),
            path.size() + 2 + std::string("cannot save the elevation map: ").size());
  m = sample_map();
  m.resolution_m = 0.0;
  EXPECT_EQ(
      save_elevation_map(path, m),
      path + ": cannot save the elevation map: resolution must be a finite number > 0, got 0");
  EXPECT_TRUE(list_dir(dir).empty());
}

}  // namespace
}  // namespace carril::loader
