#include "loader/TuningLoader.hpp"

#include "loader/SettingsYaml.hpp"

namespace carril::loader {

bool load_tuning(const std::string& path, Tuning& out, std::string& error) {
  Tuning tuning;
  const bool ok = strict::guarded(path, error, [&] {
    const strict::Node root = strict::parse_document(strict::read_file(path), &path);
    parse_settings(root, SettingFile::Tuning, tuning.settings);
    tuning.source_path = path;
  });
  if (ok) out = tuning;
  return ok;
}

}  // namespace carril::loader
