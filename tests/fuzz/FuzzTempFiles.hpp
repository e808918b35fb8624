#pragma once
// Fuzz inputs as files, for loaders that take a path: one private directory per fuzzing process
// (in /dev/shm when there is one: tmpfs, no disk writes at thousands of executions per second),
// removed at exit.
#include <cstddef>
#include <string>
#include <string_view>

namespace carril::fuzz {

// This process's directory (created on the first call).
const std::string& temp_dir();

// Writes `bytes` to temp_dir()/name, replacing it; returns the full path. Aborts on an I/O error
// (the harness is broken, not the parser).
std::string write_temp_file(const std::string& name, std::string_view bytes);

// With CARRIL_FUZZ_PRINT set (running a target on single files: `fuzz_robot FILE`), prints
// "ok" or the loader's message, to see what an input does.
void print_outcome(bool ok, const std::string& error);

// The input as text.
inline std::string_view as_text(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace carril::fuzz
