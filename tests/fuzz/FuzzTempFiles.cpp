#include "FuzzTempFiles.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace carril::fuzz {

namespace {

void remove_dir() {
  std::error_code ec;
  std::filesystem::remove_all(temp_dir(), ec);
}

}  // namespace

const std::string& temp_dir() {
  static const std::string dir = [] {
    std::string base = "/dev/shm";
    if (!std::filesystem::is_directory(base)) {
      const char* t = std::getenv("TMPDIR");
      base = t != nullptr && t[0] != '\0' ? t : "/tmp";
    }
    std::string tmpl = base + "/carril-fuzz.XXXXXX";
    if (mkdtemp(tmpl.data()) == nullptr) {
      std::perror("carril fuzz: mkdtemp");
      std::abort();
    }
    return tmpl;
  }();
  static const bool registered = [] { return std::atexit(remove_dir) == 0; }();
  (void)registered;
  return dir;
}

std::string write_temp_file(const std::string& name, std::string_view bytes) {
  const std::string path = temp_dir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "carril fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

void print_outcome(bool ok, const std::string& error) {
  static const bool print = std::getenv("CARRIL_FUZZ_PRINT") != nullptr;
  if (print) std::fprintf(stderr, "carril fuzz: %s\n", ok ? "ok" : error.c_str());
}

}  // namespace carril::fuzz
