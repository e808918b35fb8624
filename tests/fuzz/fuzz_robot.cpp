// Fuzz target: robot presets (loader/RobotLoader), read from a file as carril_sim and
// carril_controller read them. A crash, leak or UB report is a bug; a rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "loader/RobotLoader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      carril::fuzz::write_temp_file("robot.yaml", carril::fuzz::as_text(data, size));
  carril::loader::RobotSpec spec;
  std::string error;
  const bool ok = carril::loader::load_robot_preset(path, spec, error);
  carril::fuzz::print_outcome(ok, error);
  if (!ok && error.empty()) std::abort();
  return 0;
}
