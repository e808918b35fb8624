// Issue 47 item 7: docs/architecture.md's layer table is the build's: the same firmware layers,
// in the order firmware/CMakeLists.txt declares them, each on the layers it names (DEPENDS).
// CARRIL_LAYERS is "name:dep,dep|name:...", collected by carril_firmware_layer() at configure
// time.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using Layer = std::pair<std::string, std::set<std::string>>;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(part);
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" `");
  const auto e = s.find_last_not_of(" `");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<Layer> built_layers() {
  std::vector<Layer> out;
  for (const std::string& entry : split(CARRIL_LAYERS, '|')) {
    const auto colon = entry.find(':');
    std::set<std::string> deps;
    for (const std::string& d : split(entry.substr(colon + 1), ',')) {
      if (!d.empty()) deps.insert(d);
    }
    out.emplace_back(entry.substr(0, colon), deps);
  }
  return out;
}

// The rows of the table under "## Layers the build enforces": | `name` | `dep`, `dep` | ... |
std::vector<Layer> documented_layers(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  bool in_section = false;
  std::vector<Layer> out;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) in_section = line == "## Layers the build enforces";
    if (!in_section || line.rfind("| `", 0) != 0) continue;
    const std::vector<std::string> cells = split(line, '|');
    if (cells.size() < 3) continue;
    std::set<std::string> deps;
    for (const std::string& d : split(cells[2], ',')) {
      const std::string t = trim(d);
      if (!t.empty() && t != "(hal)") deps.insert(t);
    }
    out.emplace_back(trim(cells[1]), deps);
  }
  return out;
}

TEST(LayersDoc, TheDocumentedLayersAreTheBuildsInOrderWithTheirDependencies) {
  const std::vector<Layer> built = built_layers();
  const std::vector<Layer> doc =
      documented_layers(std::string(CARRIL_SOURCE_DIR) + "/docs/architecture.md");
  ASSERT_GE(built.size(), 10U);
  ASSERT_EQ(doc.size(), built.size())
      << "docs/architecture.md lists " << doc.size() << " layers, the build has " << built.size();
  for (std::size_t i = 0; i < built.size(); ++i) {
    EXPECT_EQ(doc[i].first, built[i].first) << "row " << i + 1;
    EXPECT_EQ(doc[i].second, built[i].second) << "layer " << built[i].first << "'s dependencies";
  }
}

}  // namespace
