// Fuzz target: component tuning files (loader/TuningLoader), then their settings applied to a
// default firmware configuration as carril_controller does. A crash, leak or UB report is a bug;
// a rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "loader/TuningLoader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      carril::fuzz::write_temp_file("tuning.yaml", carril::fuzz::as_text(data, size));
  carril::loader::Tuning tuning;
  std::string error;
  if (!carril::loader::load_tuning(path, tuning, error)) {
    carril::fuzz::print_outcome(false, error);
    if (error.empty()) std::abort();
    return 0;
  }
  carril::fw::FirmwareConfig c;
  const bool ok = carril::loader::apply_settings(tuning.settings, c, error);
  carril::fuzz::print_outcome(ok, error);
  if (!ok && error.empty()) std::abort();
  return 0;
}
