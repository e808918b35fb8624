#include "loader/StrictYaml.hpp"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "loader/YamlPrecheck.hpp"

namespace carril::loader::strict {

namespace {

constexpr std::size_t kMaxQuoted = 60;  // long scalars are cut in messages

// A key a carril file could have, misspelt or not: 1 to 64 letters, digits, '_', '-' or '.'.
// Anything else is not echoed in messages.
bool looks_like_key(const std::string& k) {
  if (k.empty() || k.size() > 64) return false;
  return std::all_of(k.begin(), k.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (std::size_t i = 0; i < s.size() && i < kMaxQuoted; ++i) {
    const char c = s[i];
    if (c == '\n') {
      out += "\\n";
    } else if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else {
      out += c;
    }
  }
  if (s.size() > kMaxQuoted) out += "...";
  return out + "\"";
}

std::string join(const std::vector<std::string_view>& names) {
  std::string out;
  for (auto n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

// Plain YAML scalar text of an integer: optional sign, then digits only.
bool is_integer_text(std::string_view s) {
  if (!s.empty() && (s.front() == '-' || s.front() == '+')) s.remove_prefix(1);
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

enum class NumParse { Ok, NotANumber, NotFinite };

// std::from_chars, unlike strtod, is locale-free and raises no floating-point exceptions on
// overflow (the tests run with FE_OVERFLOW trapped).
NumParse parse_double(std::string_view s, double& out) {
  if (s == ".inf" || s == "+.inf" || s == "-.inf" || s == ".Inf" || s == "+.Inf" || s == "-.Inf" ||
      s == ".INF" || s == "+.INF" || s == "-.INF" || s == ".nan" || s == ".NaN" || s == ".NAN") {
    return NumParse::NotFinite;
  }
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty() || s.front() == '+' || (s.front() == '-' && s.size() > 1 && s[1] == '+')) {
    return NumParse::NotANumber;
  }
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec == std::errc::result_out_of_range) return NumParse::NotFinite;
  if (ec != std::errc() || ptr != s.data() + s.size()) return NumParse::NotANumber;
  if (!std::isfinite(out)) return NumParse::NotFinite;
  return NumParse::Ok;
}

// Reads the whole stream as yaml-cpp's LoadAll would, building nothing, and throws LoadError
// where the parser stops making progress. yaml-cpp 0.7 (Debian 12's) has a parser that, on a
// stray ',' outside any [ ] or { }, hands out the same empty document again and again without
// reading on, so LoadAll never returns and grows its list of documents until memory runs out
// (jbeder/yaml-cpp#1040, fixed upstream by #1319 after 0.8.0). Found by fuzzing (tests/fuzz).
// Every real document, an empty one included, starts after the previous one's start, so a
// document that starts where the previous one started is that loop.
void check_parser_progress(const std::string& text, const std::string* file) {
  class Starts : public YAML::EventHandler {
   public:
    void OnDocumentStart(const YAML::Mark& mark) override { last = mark; }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
    void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  const std::string&) override {}
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                         YAML::EmitterStyle::value) override {}
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                    YAML::EmitterStyle::value) override {}
    void OnMapEnd() override {}
    YAML::Mark last = YAML::Mark::null_mark();
  };
  std::istringstream in(text);
  YAML::Parser parser(in);
  Starts starts;
  int previous = -1;
  while (parser.HandleNextDocument(starts)) {
    if (starts.last.pos == previous) {
      const auto at = static_cast<std::size_t>(previous);
      const std::string what =
          at < text.size() ? "'" + std::string(1, text[at]) + "'" : "the end of the file";
      throw LoadError(*file + ":" + std::to_string(starts.last.line + 1) +
                      ": invalid YAML: unexpected " + what + " at column " +
                      std::to_string(starts.last.column + 1) +
                      " (a ',' belongs inside [ ] or { })");
    }
    previous = starts.last.pos;
  }
}
}  // namespace

bool Range::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::describe() const {
  if (std::isinf(hi)) return std::string(lo_open ? "> " : ">= ") + format_number(lo);
  if (std::isinf(lo)) return std::string(hi_open ? "< " : "<= ") + format_number(hi);
  return std::string("in ") + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
         (hi_open ? ")" : "]");
}

std::string format_number(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

int Node::line() const {
  if (!node_.IsDefined()) return 0;
  const YAML::Mark m = node_.Mark();
  return m.is_null() || m.line < 0 ? 0 : m.line + 1;
}

void Node::fail(const std::string& what) const {
  std::string msg = *file_;
  if (const int l = line(); l > 0) msg += ":" + std::to_string(l);
  msg += ": " + (path_.empty() ? std::string("(top level)") : path_) + ": " + what;
  throw LoadError(msg);
}

bool Node::has_explicit_tag() const {
  // "?": no tag (plain scalars, untagged collections); "!": the non-specific tag of quoted
  // scalars (and of a bare "!"), i.e. a string; "": null.
  if (!node_.IsDefined()) return false;
  const std::string& t = node_.Tag();
  return !t.empty() && t != "?" && t != "!";
}

std::string Node::tag_text() const {
  const std::string& t = node_.Tag();
  constexpr std::string_view kCore = "tag:yaml.org,2002:";
  if (t.rfind(kCore, 0) == 0) return "!!" + t.substr(kCore.size());
  return t.size() > kMaxQuoted ? t.substr(0, kMaxQuoted) + "..." : t;
}

void Node::reject_tag(const std::string& what) const {
  if (has_explicit_tag()) expected(what);
}

std::string Node::describe() const {
  if (!node_.IsDefined()) return "nothing";
  if (root_ && node_.IsScalar()) {
    // The whole document is one scalar: a file of another kind, whose bytes are not echoed.
    return "a single value of " + std::to_string(node_.Scalar().size()) +
           " bytes (is this the right file?)";
  }
  std::string tag;
  if (has_explicit_tag()) tag = tag_text() + " ";
  switch (node_.Type()) {
    case YAML::NodeType::Null:
      return tag + "null";
    case YAML::NodeType::Map:
      return tag + "a map";
    case YAML::NodeType::Sequence:
      return tag + "a list";
    case YAML::NodeType::Scalar:
      return tag + quoted(node_.Scalar());
    default:
      return "nothing";
  }
}

std::string Node::raw() const {
  if (!node_.IsScalar() || node_.Tag() != "?") return describe();
  const std::string& s = node_.Scalar();
  return s.size() > kMaxQuoted ? s.substr(0, kMaxQuoted) + "..." : s;
}

Node Node::child(const YAML::Node& n, std::string_view key) const {
  return Node(n, path_.empty() ? std::string(key) : path_ + "." + std::string(key), file_);
}

void Node::expect_map(std::initializer_list<std::string_view> allowed) const {
  expect_map(std::vector<std::string_view>(allowed));
}

void Node::expect_map(const std::vector<std::string>& allowed) const {
  expect_map(std::vector<std::string_view>(allowed.begin(), allowed.end()));
}

void Node::expect_map(const std::vector<std::string_view>& allowed) const {
  if (!node_.IsMap()) expected("a map");
  reject_tag("a map");
  std::vector<std::pair<std::string, int>> seen;  // key, line
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const Node key_as_node(it->first, path_, file_);
    if (!it->first.IsScalar()) key_as_node.expected("a string key");
    key_as_node.reject_tag("a string key");
    const std::string& key = it->first.Scalar();
    const Node key_node = child(it->first, key);
    for (const auto& [k, l] : seen) {
      if (k == key) key_node.fail("duplicate key (first at line " + std::to_string(l) + ")");
    }
    bool ok = false;
    for (auto a : allowed) ok = ok || a == key;
    if (!ok && !looks_like_key(key)) {
      // Most likely a file of another kind (a password file named as a map): its bytes are not
      // echoed, only what was expected.
      Node(it->first, path_, file_)
          .fail("expected a map of keys (" + join(allowed) + "), got a key of " +
                std::to_string(key.size()) + " bytes that is not a name (is this the right file?)");
    }
    if (!ok) key_node.fail("unknown key (allowed: " + join(allowed) + ")");
    seen.emplace_back(key, key_node.line());
  }
}

std::optional<Node> Node::get(std::string_view key) const {
  if (!node_.IsMap()) expected("a map");
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return child(it->second, key);
  }
  return std::nullopt;
}

Node Node::child_path(std::string_view key) const {
  return child(node_, key);
}

Node Node::at(std::string_view key) const {
  if (auto n = get(key)) return *n;
  // The parent's node carries the line; the path names the missing key in full.
  child_path(key).fail("missing required key");
}

std::vector<Node> Node::items(std::size_t min_size) const {
  if (!node_.IsSequence()) expected("a list");
  reject_tag("a list");
  if (node_.size() < min_size) {
    expected("a list of at least " + std::to_string(min_size) + " items",
             "a list of " + std::to_string(node_.size()));
  }
  std::vector<Node> out;
  out.reserve(node_.size());
  for (std::size_t i = 0; i < node_.size(); ++i) {
    out.emplace_back(node_[i], path_ + "[" + std::to_string(i) + "]", file_);
  }
  return out;
}

std::string Node::plain_number_text() const {
  // A quoted scalar ("240") is a string in YAML, so it is not accepted as a number.
  if (!node_.IsScalar() || node_.Tag() != "?") expected("a number");
  return node_.Scalar();
}

double Node::number() const {
  double v = 0.0;
  switch (parse_double(plain_number_text(), v)) {
    case NumParse::Ok:
      return v;
    case NumParse::NotFinite:
      expected("a finite number", raw());
    case NumParse::NotANumber:
    default:
      expected("a number");
  }
}

double Node::number(const Range& range) const {
  const double v = number();
  if (!range.contains(v)) expected("a number " + range.describe(), raw());
  return v;
}

std::int64_t Node::integer(std::int64_t lo, std::int64_t hi) const {
  constexpr auto kMin = std::numeric_limits<std::int64_t>::min();
  constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
  const std::string what =
      lo == kMin && hi == kMax ? "an integer"
      : hi == kMax             ? "an integer >= " + std::to_string(lo)
                   : "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const std::string text = plain_number_text();
  std::string_view s = text;
  if (!is_integer_text(s)) {
    double ignored = 0.0;
    if (parse_double(s, ignored) == NumParse::NotANumber) expected("an integer");
    expected(what, raw());  // 1.5, 1e3: a number, but not an integer
  }
  if (s.front() == '+') s.remove_prefix(1);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || v < lo || v > hi) expected(what, raw());
  return v;
}

std::uint64_t Node::unsigned_integer() const {
  const std::string what = "an integer >= 0";
  const std::string text = plain_number_text();
  std::string_view s = text;
  if (!is_integer_text(s)) {
    double ignored = 0.0;
    if (parse_double(s, ignored) == NumParse::NotANumber) expected("an integer");
    expected(what, raw());
  }
  if (s.front() == '-') expected(what, raw());
  if (s.front() == '+') s.remove_prefix(1);
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) {
    expected("an integer in [0, 18446744073709551615]", raw());
  }
  return v;
}

bool Node::boolean() const {
  // YAML 1.2 core schema spellings only; yes/no/on/off are not booleans here.
  if (node_.IsScalar() && node_.Tag() == "?") {
    const std::string& s = node_.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  expected("true or false");
}

std::string Node::string() const {
  if (!node_.IsScalar()) expected("a string");
  reject_tag("a string");
  return node_.Scalar();
}

std::string Node::one_of(std::initializer_list<std::string_view> allowed) const {
  const std::string s = string();
  for (auto a : allowed) {
    if (a == s) return s;
  }
  expected(allowed.size() == 1 ? std::string(*allowed.begin())
                               : "one of " + join(std::vector<std::string_view>(allowed)));
}

Node parse_document(const std::string& text, const std::string* file) {
  std::vector<YAML::Node> docs;
  if (const std::string e = precheck_yaml(text); !e.empty()) throw LoadError(*file + ":" + e);
  try {
    check_parser_progress(text, file);
    docs = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    std::string msg = *file;
    if (!e.mark.is_null() && e.mark.line >= 0) msg += ":" + std::to_string(e.mark.line + 1);
    throw LoadError(msg + ": invalid YAML: " + e.msg);
  }
  if (docs.empty()) throw LoadError(*file + ": (top level): expected a map, got an empty file");
  if (docs.size() > 1) {
    Node(docs[1], "(top level)", file)
        .expected("one YAML document", std::to_string(docs.size()) + " documents");
  }
  return Node(docs[0], "", file, /*root=*/true);
}

std::string parse_name(const Node& n) {
  constexpr std::size_t kMaxNameLength = 64;
  const std::string s = n.string();
  const bool ok =
      !s.empty() && s.size() <= kMaxNameLength && std::all_of(s.begin(), s.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
      });
  if (!ok) n.expected("a name of 1 to 64 letters, digits, '_' or '-'");
  return s;
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw LoadError(path + ": cannot open");
  // Checked before reading: a huge file (or /dev/zero behind a name) is refused, not parsed.
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw LoadError(path + ": cannot read its size");
  if (size > kMaxYamlBytes) {
    throw LoadError(path + ": " + std::to_string(size) + " bytes, more than the " +
                    std::to_string(kMaxYamlBytes) + " a carril YAML file may have");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LoadError(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw LoadError(path + ": cannot read");
  return ss.str();
}

}  // namespace carril::loader::strict
