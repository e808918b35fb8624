// Fuzz target: the YAML pre-check (loader/YamlPrecheck) on any bytes, and what it lets through
// handed to parse_document as every loader does. A crash, hang, leak or UB report is a bug; a
// refusal must name a line of the text and quote none of its bytes past the fixed wording.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "loader/StrictYaml.hpp"
#include "loader/YamlPrecheck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(carril::fuzz::as_text(data, size));
  const std::string e = carril::loader::strict::precheck_yaml(text);
  if (!e.empty()) {
    // "<line>: invalid YAML: ..." with a line the text has.
    const std::size_t colon = e.find(':');
    if (colon == std::string::npos || colon == 0) std::abort();
    const unsigned long line = std::strtoul(e.substr(0, colon).c_str(), nullptr, 10);
    std::size_t lines = 1;
    for (char c : text) lines += c == '\n';
    if (line < 1 || line > lines) std::abort();
    if (e.compare(colon, 16, ": invalid YAML: ") != 0) std::abort();
    carril::fuzz::print_outcome(false, e);
    return 0;
  }
  static const std::string file = "precheck.yaml";
  try {
    carril::loader::strict::parse_document(text, &file);
    carril::fuzz::print_outcome(true, "");
  } catch (const carril::loader::strict::LoadError& err) {
    carril::fuzz::print_outcome(false, err.what());
  }
  return 0;
}
