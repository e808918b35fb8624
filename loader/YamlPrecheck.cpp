#include "loader/YamlPrecheck.hpp"

#include <cstddef>

namespace carril::loader::strict {
namespace {

bool blank(char c) {
  return c == ' ' || c == '\t';
}

// Columns of leading spaces; a line of only blanks or a comment counts as empty (npos).
std::size_t indent_of(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && blank(line[i])) ++i;
  if (i == line.size() || line[i] == '#' || line[i] == '\r') return std::string_view::npos;
  return i;
}

struct LineScan {
  std::string error;         // "" when the line is fine
  bool opens_block = false;  // it ends with a block scalar indicator (| or >)
};

// One line, outside any block scalar. `flow` is the [ ] { } depth carried across lines.
LineScan scan_line(std::string_view line, int& flow) {
  LineScan out;
  // Where a scalar may start: the line's first non-blank, after "- ", ": ", "? ", and inside
  // [ ] or { } after '[', '{' and ','.
  bool at_start = true;
  std::size_t last_token = std::string_view::npos;  // the last non-blank outside quotes
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (blank(c) || c == '\r') continue;
    if (c == '#' && (i == 0 || blank(line[i - 1]))) break;  // a comment: the rest of the line
    if ((c == '"' || c == '\'') && at_start) {
      std::size_t j = i + 1;
      bool closed = false;
      for (; j < line.size(); ++j) {
        if (c == '"' && line[j] == '\\') {
          ++j;  // an escape: the next byte is part of the string
        } else if (line[j] == c) {
          if (c == '\'' && j + 1 < line.size() && line[j + 1] == '\'') {
            ++j;  // '' inside a single-quoted string is one quote
          } else {
            closed = true;
            break;
          }
        }
      }
      if (!closed) {
        out.error = std::string("the ") + (c == '"' ? "double" : "single") + " quote at column " +
                    std::to_string(i + 1) +
                    " is not closed on its line (a quoted string must end on the line it "
                    "starts)";
        return out;
      }
      i = j;
      last_token = j;
      at_start = false;
      continue;
    }
    const bool next_blank = i + 1 >= line.size() || blank(line[i + 1]) || line[i + 1] == '\r';
    if (c == '[' || c == '{') {
      ++flow;
      at_start = true;
    } else if (c == ']' || c == '}') {
      if (flow > 0) --flow;
      at_start = false;
    } else if (c == ',' && flow > 0) {
      at_start = true;
    } else if ((c == '-' || c == '?' || c == ':') && next_blank) {
      at_start = true;  // a sequence entry, a complex key, or a value follows
    } else if (c == ':' && flow > 0) {
      at_start = true;  // {a:"b"} is a key and a quoted value in flow style
    } else {
      at_start = false;  // inside a plain scalar: a quote here is just a character
    }
    last_token = i;
  }
  if (last_token != std::string_view::npos && flow == 0) {
    // "key: |", "key: >-", "- |2": the following more indented lines are the scalar's text.
    std::size_t k = last_token;
    while (k > 0 && (line[k] == '-' || line[k] == '+' || (line[k] >= '1' && line[k] <= '9'))) --k;
    if ((line[k] == '|' || line[k] == '>') && (k == 0 || blank(line[k - 1]))) {
      out.opens_block = true;
    }
  }
  return out;
}

}  // namespace

std::string precheck_yaml(std::string_view text) {
  int flow = 0;
  bool in_block = false;
  std::size_t block_parent = 0;  // indentation of the line that opened the block scalar
  std::size_t line_no = 0;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(begin, end - begin);
    ++line_no;
    const std::size_t indent = indent_of(line);
    if (in_block && (indent == std::string_view::npos || indent > block_parent)) {
      // A line of the block scalar's text (blank lines included): quotes are literal there.
    } else {
      in_block = false;
      if (indent != std::string_view::npos) {
        const LineScan s = scan_line(line, flow);
        if (!s.error.empty()) return std::to_string(line_no) + ": invalid YAML: " + s.error;
        if (s.opens_block) {
          in_block = true;
          block_parent = indent;
        }
      }
    }
    if (end == text.size()) break;
    begin = end + 1;
  }
  return "";
}

}  // namespace carril::loader::strict
