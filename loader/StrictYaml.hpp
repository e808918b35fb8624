#pragma once
// Strict reading of yaml-cpp nodes for every carril file (robot descriptions, missions, tuning,
// scenarios): every accessor checks type and range and, on the first problem, throws LoadError
// carrying one message
//   "<file>:<line>: <key.path[i]>: expected <what>, got <what>".
// yaml-cpp's own conversions (as<T>) are avoided: they accept "1.5" as an int prefix, yes/on as
// booleans and quoted numbers, which a strict format must reject.
// Internal to the loaders (it throws, and yaml-cpp needs exceptions): the public loader functions
// catch everything with guarded() and return ok + one message.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace carril::loader::strict {

class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A closed/open interval for numbers; an infinite bound is printed as "> lo" / ">= lo".
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
  static Range closed_open(double lo, double hi) { return {lo, hi, false, true}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, false};
  }

  bool contains(double v) const;
  std::string describe() const;  // "(0, 0.5]", "> 0", ">= 0"
};

// Shortest round-trip-ish text for a number in a message ("0.5", "86400", "1e-09").
std::string format_number(double v);

// A YAML node together with its key path and file, so any check can produce a full message.
class Node {
 public:
  // root: the whole document (a scalar there is a file of another kind: never echoed).
  Node(YAML::Node node, std::string path, const std::string* file, bool root = false)
      : node_(std::move(node)), path_(std::move(path)), file_(file), root_(root) {}

  const YAML::Node& yaml() const { return node_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }
  int line() const;  // 1-based; 0 when yaml-cpp has no mark

  // "<file>:<line>: <path>: <what>" (path "(top level)" for the document itself).
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void expected(const std::string& what, const std::string& got) const {
    fail("expected " + what + ", got " + got);
  }
  [[noreturn]] void expected(const std::string& what) const { expected(what, describe()); }

  // What the node is, for type errors: a map, a list, null, or the scalar in quotes.
  std::string describe() const;
  // The scalar as written (for range errors: "got -1"); describe() for non-scalars.
  std::string raw() const;

  // Maps: checks the node is a map whose keys are unique scalars from `allowed`.
  void expect_map(std::initializer_list<std::string_view> allowed) const;
  void expect_map(const std::vector<std::string>& allowed) const;
  std::optional<Node> get(std::string_view key) const;
  Node at(std::string_view key) const;  // required key
  // This node under the path of `key` (for messages about a key that is absent).
  Node child_path(std::string_view key) const;
  std::optional<Node> get(std::string_view key, bool required) const {
    return required ? std::optional<Node>(at(key)) : get(key);
  }

  // Lists: checks the node is a list with at least `min_size` items.
  std::vector<Node> items(std::size_t min_size = 0) const;

  // Scalars. Numbers must be plain (unquoted) and finite; integers must have no fraction.
  double number() const;
  double number(const Range& range) const;
  std::int64_t integer(std::int64_t lo, std::int64_t hi) const;
  std::uint64_t unsigned_integer() const;
  bool boolean() const;
  std::string string() const;
  std::string one_of(std::initializer_list<std::string_view> allowed) const;

 private:
  void expect_map(const std::vector<std::string_view>& allowed) const;
  Node child(const YAML::Node& n, std::string_view key) const;
  std::string plain_number_text() const;  // checks "plain scalar", returns its text
  // An explicit tag (!!str, !!int, !foo, ...): every one is rejected, so a value means what it
  // looks like. Plain scalars and collections carry "?", quoted scalars "!".
  bool has_explicit_tag() const;
  std::string tag_text() const;  // "!!str" for the core schema's tags, else as written
  void reject_tag(const std::string& what) const;

  YAML::Node node_;
  std::string path_;
  const std::string* file_;
  bool root_ = false;
};

// The largest YAML file read_file() accepts [bytes]: every carril file is far smaller.
constexpr std::uintmax_t kMaxYamlBytes = 4U << 20U;

// Parses `text` as exactly one YAML document; syntax errors (and what precheck_yaml() finds)
// become LoadError with file:line.
Node parse_document(const std::string& text, const std::string* file);

// Reads a whole file; throws LoadError "<path>: cannot open" when it is not a readable file.
std::string read_file(const std::string& path);

// A name (robot, scenario): 1 to 64 letters, digits, '_' or '-' (it may become a directory name).
std::string parse_name(const Node& n);

// Runs `body`, turning anything it throws (LoadError, yaml-cpp's, bad_alloc) into `error`, so
// the callers of a loader only ever see ok/error. `path` prefixes messages that lack a location.
template <typename F>
bool guarded(const std::string& path, std::string& error, F&& body) {
  try {
    body();
    return true;
  } catch (const LoadError& e) {
    error = e.what();
  } catch (const YAML::Exception& e) {
    error = path + ": " + e.what();
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
  } catch (...) {
    error = path + ": unknown error";
  }
  return false;
}

}  // namespace carril::loader::strict
