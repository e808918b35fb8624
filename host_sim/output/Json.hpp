#pragma once
// Minimal JSON text helpers for the run's summary: a flat, pretty-printed object whose key order
// is the writer's call order (the summary's key order is a contract).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace carril::sim::json {

// `"..."` with JSON escaping (quote, backslash, control characters).
std::string quote(std::string_view s);
// Up to 9 significant digits, locale-independent; null when not finite.
std::string number(double v);
std::string number(std::optional<double> v);

// Builds `{ "key": value, ... }` with 2-space indentation, one key per line.
class ObjectWriter {
 public:
  void raw(std::string_view key, std::string_view json_value);
  void str(std::string_view key, std::string_view v) { raw(key, quote(v)); }
  void num(std::string_view key, double v) { raw(key, number(v)); }
  void num(std::string_view key, std::optional<double> v) { raw(key, number(v)); }
  void integer(std::string_view key, long v) { raw(key, std::to_string(v)); }
  void boolean(std::string_view key, bool v) { raw(key, v ? "true" : "false"); }
  void str_or_null(std::string_view key, std::string_view v) {
    raw(key, v.empty() ? std::string("null") : quote(v));
  }
  void str_array(std::string_view key, const std::vector<std::string>& items);
  // The finished object, ending in a newline.
  std::string finish() const;
  // The finished object on one line, as a value inside another object: {"a": 1, "b": 2}.
  std::string finish_inline() const;

 private:
  std::vector<std::string> entries_;  // `"key": value`, without indentation or comma
};

}  // namespace carril::sim::json
