// Fuzz target: candump log lines (hal/can/Candump, the --can-log format), read back by
// parse_candump; a parsed frame must be one a CanBus accepts and must format again.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "hal/can/Candump.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string line(carril::fuzz::as_text(data, size));  // NUL-terminated, as from fgets
  carril::hal::CanFrame f;
  carril::hal::TimeNs t = 0;
  if (!carril::hal::parse_candump(line.c_str(), f, t)) return 0;
  if (f.len > carril::hal::kCanMaxLen) std::abort();
  char buf[carril::hal::kCandumpMaxLine + 1];
  if (carril::hal::format_candump(f, t, "can0", buf, sizeof buf) == 0) std::abort();
  return 0;
}
