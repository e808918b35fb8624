#pragma once
// Console on the process's standard output: one write(2) per line, so lines from the slow rate
// group's thread never interleave with the main thread's stdio mid-line.
#include "hal/Console.hpp"

namespace carril::hal {

class StdoutConsole final : public Console {
 public:
  void write_line(const char* line) override;
};

}  // namespace carril::hal
