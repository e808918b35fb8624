// Fuzz target: mission files (loader/MissionLoader) for the campero robot. A crash, leak or UB
// report is a bug; a rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzRobot.hpp"
#include "FuzzTempFiles.hpp"
#include "loader/MissionLoader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto& robot = carril::fuzz::campero();
  const std::string path =
      carril::fuzz::write_temp_file("mission.yaml", carril::fuzz::as_text(data, size));
  carril::loader::MissionSpec mission;
  std::string error;
  const bool ok = carril::loader::load_mission(path, robot, mission, error);
  carril::fuzz::print_outcome(ok, error);
  if (!ok && error.empty()) std::abort();
  return 0;
}
