#pragma once
// Writing a file so that a reader (or a power cut) sees either the old file or the complete new
// one, never a partial one: saved maps and exported costmaps.
#include <optional>
#include <string>
#include <string_view>

namespace carril::loader {

// Writes `bytes` to `path` atomically: a temporary file in the same directory, write, fsync,
// rename over `path`, fsync the directory. nullopt on success; else "<path>: <what failed>:
// <errno text>", and no temporary file is left behind.
std::optional<std::string> write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace carril::loader
