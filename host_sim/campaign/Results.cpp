#include "host_sim/campaign/Results.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host_sim/campaign/Runner.hpp"
#include "host_sim/campaign/Variant.hpp"
#include "loader/AtomicWrite.hpp"

namespace carril::sim::campaign {

namespace {
namespace fs = std::filesystem;
using Fields = std::vector<std::pair<std::string, std::string>>;

// A small reader for the simulator's summary: objects, lists, strings, numbers, literals.
class JsonReader {
 public:
  explicit JsonReader(const std::string& s) : s_(s) {}

  bool object(const std::string& prefix, Fields& out) {
    skip();
    if (!eat('{')) return false;
    skip();
    if (eat('}')) return true;
    for (;;) {
      std::string key;
      skip();
      if (!string(key)) return false;
      skip();
      if (!eat(':')) return false;
      skip();
      const std::string name = prefix.empty() ? key : prefix + "." + key;
      if (peek() == '{') {
        if (!object(name, out)) return false;
      } else {
        std::string v;
        if (!value(v)) return false;
        out.emplace_back(name, v);
      }
      skip();
      if (eat('}')) return true;
      if (!eat(',')) return false;
    }
  }
  bool at_end() {
    skip();
    return i_ == s_.size();
  }

 private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  bool eat(char c) {
    if (peek() != c) return false;
    ++i_;
    return true;
  }
  void skip() {
    while (i_ < s_.size() &&
           (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t')) {
      ++i_;
    }
  }
  bool string(std::string& out) {
    if (!eat('"')) return false;
    while (i_ < s_.size()) {
      const char c = s_[i_++];
      if (c == '"') return true;
      if (c != '\\') {
        out.push_back(c);
        continue;
      }
      if (i_ >= s_.size()) return false;
      const char e = s_[i_++];
      switch (e) {
        case 'n':
          out.push_back('\n');
          break;
        case 't':
          out.push_back('\t');
          break;
        case 'r':
          out.push_back('\r');
          break;
        case 'b':
          out.push_back('\b');
          break;
        case 'f':
          out.push_back('\f');
          break;
        case 'u':
          if (i_ + 4 > s_.size()) return false;
          out.push_back('?');  // control characters only, in the simulator's output
          i_ += 4;
          break;
        default:
          out.push_back(e);
      }
    }
    return false;
  }
  // A scalar, or a list of scalars joined with ';'.
  bool value(std::string& out) {
    if (peek() == '"') return string(out);
    if (eat('[')) {
      skip();
      if (eat(']')) return true;
      for (bool first = true;; first = false) {
        std::string item;
        skip();
        if (!value(item)) return false;
        if (!first) out.push_back(';');
        out += item;
        skip();
        if (eat(']')) return true;
        if (!eat(',')) return false;
      }
    }
    const std::size_t b = i_;
    while (i_ < s_.size() &&
           std::string_view("+-.0123456789eEtruefalsn").find(s_[i_]) != std::string_view::npos) {
      ++i_;
    }
    if (i_ == b) return false;
    out = s_.substr(b, i_ - b);
    if (out == "null") out.clear();
    return true;
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}
}  // namespace

std::optional<Fields> parse_summary(const std::string& text) {
  JsonReader r(text);
  Fields f;
  if (!r.object("", f) || !r.at_end()) return std::nullopt;
  return f;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q.push_back('"');
    q.push_back(c);
  }
  q.push_back('"');
  return q;
}

const std::string& RunRow::field(const std::string& key) const {
  static const std::string kNone;
  for (const auto& [k, v] : fields) {
    if (k == key) return v;
  }
  return kNone;
}

ResultsTable load_results(const CampaignSpec& spec, const std::string& out_dir) {
  ResultsTable t;
  for (std::uint64_t i = 0; i < spec.variant_count(); ++i) {
    RunRow row;
    row.status = variant_status(out_dir, i);
    if (row.status.empty()) {
      ++t.missing;
      continue;
    }
    const Variant v = make_variant(spec, i);
    row.index = i;
    row.values = v.values;
    row.base_name = v.base_name;
    row.preset = v.preset;
    row.strategy = v.strategy;
    row.seed = v.seed;
    const fs::path summary = fs::path(variant_dir(out_dir, i)) / "sim" / "summary.json";
    std::ifstream in(summary, std::ios::binary);
    if (in) {  // a simulator that refused its input or crashed may have left none
      std::ostringstream s;
      s << in.rdbuf();
      const auto f = parse_summary(s.str());
      if (!f) {
        t.error = summary.string() + ": expected a JSON object (a carril_sim summary)";
        return t;
      }
      row.fields = *f;
      for (const auto& [k, val] : row.fields) {
        bool seen = false;
        for (const std::string& c : t.columns) seen = seen || c == k;
        if (!seen) t.columns.push_back(k);
      }
    }
    // Without a robot list the scenario's own preset and strategy ran: the summary says which.
    t.rows.push_back(std::move(row));
  }
  t.ok = true;
  return t;
}

std::string results_csv(const CampaignSpec& spec, const ResultsTable& t) {
  std::string csv = "index,base_scenario,preset,strategy,seed";
  for (const Perturbation& p : spec.perturbations) csv += "," + p.key;
  csv += ",status";
  for (const std::string& c : t.columns) csv += "," + csv_field(c);
  csv += "\n";
  for (const RunRow& row : t.rows) {
    csv += std::to_string(row.index) + "," + csv_field(row.base_name) + "," +
           csv_field(row.preset) + "," + csv_field(row.strategy) + "," + std::to_string(row.seed);
    for (const double x : row.values) csv += "," + number_text(x);
    csv += "," + csv_field(row.status);
    for (const std::string& c : t.columns) csv += "," + csv_field(row.field(c));
    csv += "\n";
  }
  return csv;
}

CollectResult collect_results(const CampaignSpec& spec, const std::string& out_dir) {
  CollectResult r;
  const ResultsTable t = load_results(spec, out_dir);
  r.missing = t.missing;
  if (!t.ok) {
    r.error = t.error;
    return r;
  }
  const std::string csv = results_csv(spec, t);
  if (auto e = loader::write_file_atomically((fs::path(out_dir) / "results.csv").string(), csv)) {
    r.error = *e;
    return r;
  }
  r.rows = t.rows.size();
  r.ok = true;
  return r;
}

}  // namespace carril::sim::campaign
