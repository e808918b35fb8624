// Fuzz target: ROS map_server maps (loader/OccupancyMapFile): the YAML file and its PGM image.
// The input is the YAML text, the line "%%PGM%%", then the image's bytes (no separator: all of it
// is the YAML and the image is empty); the image is written as map.pgm beside map.yaml. A crash,
// leak or UB report is a bug; a rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "FuzzTempFiles.hpp"
#include "loader/OccupancyMapFile.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::string_view kSeparator = "\n%%PGM%%\n";
  const std::string_view in = carril::fuzz::as_text(data, size);
  const std::size_t cut = in.find(kSeparator);
  const std::string_view yaml = in.substr(0, cut);
  const std::string_view pgm =
      cut == std::string_view::npos ? std::string_view{} : in.substr(cut + kSeparator.size());
  carril::fuzz::write_temp_file("map.pgm", pgm);
  const std::string path = carril::fuzz::write_temp_file("map.yaml", yaml);
  // A small buffer, so the "more cells than the buffer" path is reachable with small inputs.
  const carril::loader::OccupancyMapLoad r = carril::loader::load_occupancy_map(path, 4096);
  carril::fuzz::print_outcome(r.ok(), r.error);
  if (!r.ok()) return 0;
  const auto& info = r.map.info;
  // The contract of a loaded map: as many cells as nx * ny, each a cost value.
  if (info.nx <= 0 || info.ny <= 0 ||
      r.map.cells.size() != static_cast<std::size_t>(info.nx) * static_cast<std::size_t>(info.ny))
    std::abort();
  return 0;
}
