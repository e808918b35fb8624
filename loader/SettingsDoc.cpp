#include "loader/SettingsDoc.hpp"

#include "loader/Settings.hpp"

namespace carril::loader {

namespace {

constexpr const char* kBegin = "<!-- settings: ";
constexpr const char* kEnd = "<!-- end of settings -->";

}  // namespace

bool regenerate_settings_doc(const std::string& doc, std::string& out, std::string& error) {
  out.clear();
  std::size_t pos = 0;
  bool seen[2] = {false, false};
  while (true) {
    const std::size_t begin = doc.find(kBegin, pos);
    if (begin == std::string::npos) break;
    const std::size_t name_at = begin + std::char_traits<char>::length(kBegin);
    const std::size_t close = doc.find(" -->\n", name_at);
    if (close == std::string::npos) {
      error = "a settings marker without ' -->' at the end of its line";
      return false;
    }
    const std::string name = doc.substr(name_at, close - name_at);
    SettingFile file;
    if (name == "mission") {
      file = SettingFile::Mission;
    } else if (name == "tuning") {
      file = SettingFile::Tuning;
    } else {
      error = "settings marker '" + name + "': expected mission or tuning";
      return false;
    }
    seen[static_cast<int>(file)] = true;
    const std::size_t body = close + 5;
    const std::size_t end = doc.find(kEnd, body);
    if (end == std::string::npos) {
      error = "settings marker '" + name + "' is not closed by " + kEnd;
      return false;
    }
    out += doc.substr(pos, body - pos);
    out += settings_markdown(file);
    pos = end;
  }
  out += doc.substr(pos);
  if (!seen[0] || !seen[1]) {
    error = std::string("no ") + (seen[0] ? "tuning" : "mission") + " settings marker";
    return false;
  }
  return true;
}

}  // namespace carril::loader
