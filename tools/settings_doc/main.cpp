// carril_settings_doc: regenerates docs/configuration.md's settings tables from the settings
// tables (firmware/core/Param.hpp), or checks that they agree.
//   carril_settings_doc docs/configuration.md           rewrite the tables in place (whole file)
//   carril_settings_doc --check docs/configuration.md   exit 1 if they differ
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "loader/AtomicWrite.hpp"
#include "loader/SettingsDoc.hpp"

int main(int argc, char** argv) {
  const bool check = argc == 3 && std::strcmp(argv[1], "--check") == 0;
  if (argc != 2 && !check) {
    std::fprintf(stderr, "usage: carril_settings_doc [--check] docs/configuration.md\n");
    return 2;
  }
  const std::string path = argv[argc - 1];
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot be read\n", path.c_str());
    return 2;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  std::string out, error;
  if (!carril::loader::regenerate_settings_doc(doc, out, error)) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), error.c_str());
    return 2;
  }
  if (check) {
    if (out == doc) return 0;
    std::fprintf(stderr,
                 "%s: the settings tables differ from the code; run carril_settings_doc %s\n",
                 path.c_str(), path.c_str());
    return 1;
  }
  if (out == doc) return 0;
  if (auto err = carril::loader::write_file_atomically(path, out)) {
    std::fprintf(stderr, "%s\n", err->c_str());
    return 2;
  }
  std::printf("%s: settings tables rewritten\n", path.c_str());
  return 0;
}
