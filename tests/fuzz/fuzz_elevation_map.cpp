// Fuzz target: saved elevation maps (loader/ElevationMapFile), a binary file with a CRC-32. The
// CRC would stop nearly every mutation at the checksum, so for inputs of an even length the
// harness rewrites the last 4 bytes with the CRC of the rest (the header and cell checks behind it
// are reached); odd lengths keep the CRC as written. A crash, leak or UB report is a bug; a
// rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "loader/ElevationMapFile.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace loader = carril::loader;
  std::string bytes(carril::fuzz::as_text(data, size));
  // A valid file's length is always even (84 + 8 n + 4), so odd lengths test the CRC check.
  const std::size_t crc_at = bytes.size() - loader::kElevationMapCrcBytes;
  if (bytes.size() >= loader::kElevationMapHeaderBytes + loader::kElevationMapCrcBytes &&
      bytes.size() % 2 == 0) {
    const std::uint32_t crc = loader::crc32_ieee(bytes.data(), crc_at);
    for (std::size_t i = 0; i < 4; ++i) bytes[crc_at + i] = static_cast<char>(crc >> (8 * i));
  }
  const std::string path = carril::fuzz::write_temp_file("map.cem", bytes);
  const loader::ElevationMapLoad r = loader::load_elevation_map(path, 4096);
  carril::fuzz::print_outcome(r.ok(), r.error);
  if (!r.ok()) return 0;
  if (r.map.cells.size() != std::size_t{r.map.nx} * r.map.ny) std::abort();
  // A loaded map writes back to the same bytes.
  std::string error;
  const auto again = loader::encode_elevation_map(r.map, error);
  if (!again) std::abort();
  return 0;
}
