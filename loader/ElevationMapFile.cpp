#include "loader/ElevationMapFile.hpp"

#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>

#include "loader/AtomicWrite.hpp"

namespace carril::loader {

namespace {

// Byte offsets of the header fields (docs/map-formats.md).
constexpr std::size_t kOffVersion = 8;
constexpr std::size_t kOffResolution = 12;
constexpr std::size_t kOffNx = 20;
constexpr std::size_t kOffNy = 24;
constexpr std::size_t kOffOriginX = 28;
constexpr std::size_t kOffOriginY = 36;
constexpr std::size_t kOffFrame = 44;
constexpr std::size_t kOffCellCount = 76;
static_assert(kOffCellCount + 8 == kElevationMapHeaderBytes);

// Slicing-by-8 tables: kCrcTables[0] is the byte-wise table; kCrcTables[k][i] is the CRC of byte
// i followed by k zero bytes, so eight bytes are folded per step (about 8x the byte-wise speed).
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;
constexpr CrcTables make_crc_tables() {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (std::size_t k = 1; k < 8; ++k) {
    for (std::size_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFU];
  }
  return t;
}
constexpr CrcTables kCrcTables = make_crc_tables();

// Little-endian writers and readers, independent of the host's byte order and struct layout.
void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
}
void store_u32(unsigned char* p, std::uint32_t v) {
  p[0] = static_cast<unsigned char>(v & 0xFFU);
  p[1] = static_cast<unsigned char>((v >> 8) & 0xFFU);
  p[2] = static_cast<unsigned char>((v >> 16) & 0xFFU);
  p[3] = static_cast<unsigned char>(v >> 24);
}
void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
}
void put_f64(std::string& out, double v) {
  put_u64(out, std::bit_cast<std::uint64_t>(v));
}
std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
std::uint64_t get_u64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
float get_f32(const unsigned char* p) {
  return std::bit_cast<float>(get_u32(p));
}
double get_f64(const unsigned char* p) {
  return std::bit_cast<double>(get_u64(p));
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string cell_name(std::uint64_t index, std::uint32_t nx) {
  return "cell (" + std::to_string(index % nx) + ", " + std::to_string(index / nx) + ")";
}

// Reads up to `n` bytes at the current position; the count actually read.
std::size_t read_some(std::ifstream& in, unsigned char* dst, std::size_t n) {
  in.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n));
  return static_cast<std::size_t>(in.gcount());
}

}  // namespace

std::uint32_t crc32_ieee(const void* data, std::size_t n, std::uint32_t crc) {
  const auto* p = static_cast<const unsigned char*>(data);
  const auto& t = kCrcTables;
  crc = ~crc;
  // Bytes assembled by shifts, so the result does not depend on the host's byte order.
  for (; n >= 8; n -= 8, p += 8) {
    const std::uint32_t lo = crc ^ (std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 |
                                    std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24);
    const std::uint32_t hi = std::uint32_t{p[4]} | std::uint32_t{p[5]} << 8 |
                             std::uint32_t{p[6]} << 16 | std::uint32_t{p[7]} << 24;
    crc = t[7][lo & 0xFFU] ^ t[6][(lo >> 8) & 0xFFU] ^ t[5][(lo >> 16) & 0xFFU] ^ t[4][lo >> 24] ^
          t[3][hi & 0xFFU] ^ t[2][(hi >> 8) & 0xFFU] ^ t[1][(hi >> 16) & 0xFFU] ^ t[0][hi >> 24];
  }
  for (; n > 0; --n, ++p) crc = t[0][(crc ^ *p) & 0xFFU] ^ (crc >> 8);
  return ~crc;
}

std::optional<std::string> encode_elevation_map(const ElevationMapData& map, std::string& error) {
  const std::uint64_t count = std::uint64_t{map.nx} * map.ny;
  if (map.nx == 0 || map.ny == 0) {
    error = "empty map (nx " + std::to_string(map.nx) + ", ny " + std::to_string(map.ny) + ")";
    return std::nullopt;
  }
  if (map.cells.size() != count) {
    error = "nx * ny = " + std::to_string(count) + " but the map has " +
            std::to_string(map.cells.size()) + " cells";
    return std::nullopt;
  }
  if (!std::isfinite(map.resolution_m) || !(map.resolution_m > 0.0)) {
    error = "resolution must be a finite number > 0, got " + num(map.resolution_m);
    return std::nullopt;
  }
  if (!std::isfinite(map.origin_x_m) || !std::isfinite(map.origin_y_m)) {
    error = "origin must be finite, got (" + num(map.origin_x_m) + ", " + num(map.origin_y_m) + ")";
    return std::nullopt;
  }
  if (map.frame.empty() || map.frame.size() >= kElevationMapFrameBytes ||
      map.frame.find('\0') != std::string::npos) {
    error = "frame name must be 1 to " + std::to_string(kElevationMapFrameBytes - 1) +
            " characters without NUL, got \"" + map.frame + "\"";
    return std::nullopt;
  }
  std::string out;
  out.reserve(kElevationMapHeaderBytes + count * kElevationMapCellBytes + kElevationMapCrcBytes);
  out.append(kElevationMapMagic, sizeof kElevationMapMagic);
  put_u32(out, kElevationMapVersion);
  put_f64(out, map.resolution_m);
  put_u32(out, map.nx);
  put_u32(out, map.ny);
  put_f64(out, map.origin_x_m);
  put_f64(out, map.origin_y_m);
  std::string frame = map.frame;
  frame.resize(kElevationMapFrameBytes, '\0');
  out += frame;
  put_u64(out, count);
  // The cells straight into the sized buffer (push_back per byte is several times slower).
  const std::size_t cells_at = out.size();
  out.resize(cells_at + count * kElevationMapCellBytes);
  auto* dst = reinterpret_cast<unsigned char*>(out.data() + cells_at);
  for (const fw::ElevationCell& c : map.cells) {
    store_u32(dst, std::bit_cast<std::uint32_t>(c.height_m));
    store_u32(dst + 4, std::bit_cast<std::uint32_t>(c.variance_m2));
    dst += kElevationMapCellBytes;
  }
  put_u32(out, crc32_ieee(out.data(), out.size()));
  return out;
}

std::optional<std::string> save_elevation_map(const std::string& path,
                                              const ElevationMapData& map) {
  std::string error;
  const auto bytes = encode_elevation_map(map, error);
  if (!bytes) return path + ": cannot save the elevation map: " + error;
  return write_file_atomically(path, *bytes);
}

ElevationMapLoad load_elevation_map(const std::string& path, std::uint64_t max_cells) {
  ElevationMapLoad r;
  auto fail = [&](const std::string& what) {
    r.error = path + ": " + what;
    r.map = ElevationMapData{};
    return r;
  };
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    if (err == ENOENT) return fail("not found");
    return fail(std::string("cannot open: ") + (err != 0 ? std::strerror(err) : "unknown error"));
  }
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(0, std::ios::beg);
  if (end < 0) return fail("cannot read (not a regular file?)");
  const auto size = static_cast<std::uint64_t>(end);

  std::array<unsigned char, kElevationMapHeaderBytes> head{};
  const std::size_t got = read_some(in, head.data(), head.size());
  if (got < sizeof kElevationMapMagic && std::memcmp(head.data(), kElevationMapMagic, got) == 0) {
    return fail("truncated: expected at least " +
                std::to_string(kElevationMapHeaderBytes + kElevationMapCrcBytes) + " bytes, got " +
                std::to_string(size));
  }
  if (got < sizeof kElevationMapMagic ||
      std::memcmp(head.data(), kElevationMapMagic, sizeof kElevationMapMagic) != 0) {
    return fail("not a carril elevation map (the first 8 bytes are not \"CARRILEM\")");
  }
  const std::uint64_t min_size = kElevationMapHeaderBytes + kElevationMapCrcBytes;
  if (got < kOffVersion + 4) {
    return fail("truncated: expected at least " + std::to_string(min_size) + " bytes, got " +
                std::to_string(size));
  }
  const std::uint32_t version = get_u32(head.data() + kOffVersion);
  if (version != kElevationMapVersion) {
    return fail("unsupported format version: the file says " + std::to_string(version) +
                ", this build reads " + std::to_string(kElevationMapVersion));
  }
  if (size < min_size) {
    return fail("truncated: expected at least " + std::to_string(min_size) +
                " bytes (header and CRC), got " + std::to_string(size));
  }
  ElevationMapData& m = r.map;
  m.resolution_m = get_f64(head.data() + kOffResolution);
  m.nx = get_u32(head.data() + kOffNx);
  m.ny = get_u32(head.data() + kOffNy);
  m.origin_x_m = get_f64(head.data() + kOffOriginX);
  m.origin_y_m = get_f64(head.data() + kOffOriginY);
  const std::uint64_t cell_count = get_u64(head.data() + kOffCellCount);
  const std::uint64_t count = std::uint64_t{m.nx} * m.ny;
  if (m.nx == 0 || m.ny == 0 || cell_count != count) {
    return fail("inconsistent sizes: nx " + std::to_string(m.nx) + " * ny " + std::to_string(m.ny) +
                " = " + std::to_string(count) + " cells, but the header's cell count is " +
                std::to_string(cell_count));
  }
  if (count > max_cells) {
    return fail("too big for the configured grid: " + std::to_string(m.nx) + " x " +
                std::to_string(m.ny) + " = " + std::to_string(count) + " cells, the grid holds " +
                std::to_string(max_cells));
  }
  const std::uint64_t expected = min_size + count * kElevationMapCellBytes;
  if (size != expected) {
    return fail(std::string(size < expected ? "truncated" : "trailing bytes") + ": expected " +
                std::to_string(expected) + " bytes for " + std::to_string(m.nx) + " x " +
                std::to_string(m.ny) + " cells, got " + std::to_string(size));
  }
  // The cells' bytes go straight into the cells' storage and are decoded there in place (each
  // cell is read before it is written), so a load needs one buffer of the map's size, not two.
  static_assert(sizeof(fw::ElevationCell) == kElevationMapCellBytes);
  m.cells.resize(static_cast<std::size_t>(count));
  auto* cell_bytes = reinterpret_cast<unsigned char*>(m.cells.data());
  const std::size_t cells_bytes = m.cells.size() * kElevationMapCellBytes;
  std::array<unsigned char, kElevationMapCrcBytes> crc_bytes{};
  if (read_some(in, cell_bytes, cells_bytes) != cells_bytes ||
      read_some(in, crc_bytes.data(), crc_bytes.size()) != crc_bytes.size()) {
    return fail("read error: " + std::string(std::strerror(errno)));
  }
  const std::uint32_t stored_crc = get_u32(crc_bytes.data());
  const std::uint32_t crc =
      crc32_ieee(cell_bytes, cells_bytes, crc32_ieee(head.data(), head.size()));
  if (crc != stored_crc) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "CRC mismatch (corrupted): stored 0x%08x, computed 0x%08x",
                  stored_crc, crc);
    return fail(buf);
  }
  // The CRC only proves the bytes are what was written; the writer may still have been wrong.
  if (!std::isfinite(m.resolution_m) || !(m.resolution_m > 0.0)) {
    return fail("resolution must be a finite number > 0, got " + num(m.resolution_m));
  }
  if (!std::isfinite(m.origin_x_m) || !std::isfinite(m.origin_y_m)) {
    return fail("origin must be finite, got (" + num(m.origin_x_m) + ", " + num(m.origin_y_m) +
                ")");
  }
  const char* frame = reinterpret_cast<const char*>(head.data() + kOffFrame);
  const std::size_t frame_len = ::strnlen(frame, kElevationMapFrameBytes);
  if (frame_len == 0 || frame_len == kElevationMapFrameBytes) {
    return fail("frame name must be 1 to 31 characters followed by NUL");
  }
  m.frame.assign(frame, frame_len);
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    const unsigned char* p = cell_bytes + i * kElevationMapCellBytes;
    const float height = get_f32(p);
    const float variance = get_f32(p + 4);
    fw::ElevationCell& c = m.cells[i];
    c.height_m = height;
    c.variance_m2 = variance;
    if (!std::isfinite(c.variance_m2) || c.variance_m2 < 0.0F) {
      return fail(cell_name(i, m.nx) + ": variance must be finite and >= 0, got " +
                  num(static_cast<double>(c.variance_m2)));
    }
    if (!std::isfinite(c.height_m)) {
      if (c.observed()) {
        return fail(cell_name(i, m.nx) + ": observed cell with a non-finite height " +
                    num(static_cast<double>(c.height_m)));
      }
      c.height_m = 0.0F;  // an unobserved cell's height means nothing; keep it harmless
    }
  }
  return r;
}

}  // namespace carril::loader
