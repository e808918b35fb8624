#pragma once
// A lexical check of a carril YAML file before yaml-cpp sees it, for what yaml-cpp 0.7 accepts
// and should not: a quoted string whose closing quote is missing runs on over the following
// lines (up to the next quote, or the end of the file), so a scenario's `expect:` block can
// vanish into a string and the run passes. carril files keep every quoted string on the line it
// starts; block scalars (`|`, `>`) and comments are skipped. Returns "" when the text is fine,
// else "<line>: invalid YAML: <what>" (1-based line; the message quotes none of the file's bytes).
#include <string>
#include <string_view>

namespace carril::loader::strict {

std::string precheck_yaml(std::string_view text);

}  // namespace carril::loader::strict
