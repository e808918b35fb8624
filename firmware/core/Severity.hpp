#pragma once
// How much an event matters. Its own header so that declaring a task's overrun severity
// (TaskTable.hpp) does not pull in the whole Event record.
#include <cstdint>

namespace carril::fw {

enum class Severity : std::uint8_t { Info, Warning, Error };

inline const char* severity_name(Severity s) {
  switch (s) {
    case Severity::Info:
      return "info";
    case Severity::Warning:
      return "warning";
    case Severity::Error:
      return "error";
  }
  return "?";
}

}  // namespace carril::fw
