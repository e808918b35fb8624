#include "host_sim/output/Json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace carril::sim::json {

std::string quote(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out.push_back('"');
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out.push_back(c);  // UTF-8 bytes pass through unchanged
        }
    }
  }
  out.push_back('"');
  return out;
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  // std::to_chars ignores the locale (printf would print "0,5" under some LC_NUMERIC).
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 9);
  if (r.ec != std::errc()) return "null";
  return std::string(buf, r.ptr);
}

std::string number(std::optional<double> v) {
  return v ? number(*v) : std::string("null");
}

void ObjectWriter::raw(std::string_view key, std::string_view json_value) {
  std::string e = quote(key);
  e += ": ";
  e += json_value;
  entries_.push_back(std::move(e));
}

void ObjectWriter::str_array(std::string_view key, const std::vector<std::string>& items) {
  if (items.empty()) {
    raw(key, "[]");
    return;
  }
  std::string v = "[\n";
  for (std::size_t i = 0; i < items.size(); ++i) {
    v += "    ";
    v += quote(items[i]);
    v += i + 1 < items.size() ? ",\n" : "\n";
  }
  v += "  ]";
  raw(key, v);
}

std::string ObjectWriter::finish() const {
  std::string out = "{\n";
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    out += "  ";
    out += entries_[i];
    out += i + 1 < entries_.size() ? ",\n" : "\n";
  }
  out += "}\n";
  return out;
}

std::string ObjectWriter::finish_inline() const {
  std::string out = "{";
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (i > 0) out += ", ";
    out += entries_[i];
  }
  return out + "}";
}

}  // namespace carril::sim::json
