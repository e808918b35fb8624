#pragma once
// A campaign's results in one CSV: one row per finished variant, with what it was (index, base
// scenario, preset, strategy, seed, every perturbation value, status) and every field of its
// summary.json (nested objects flattened as "object.key", lists joined with ';').
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host_sim/campaign/CampaignFile.hpp"

namespace carril::sim::campaign {

// A flat JSON object's fields in file order, values as text (strings unescaped, null as "").
// nullopt when `text` is not one JSON object.
std::optional<std::vector<std::pair<std::string, std::string>>> parse_summary(
    const std::string& text);

// One CSV field, quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s);

// One finished variant: what it was, how it ended and its summary's fields.
struct RunRow {
  std::uint64_t index = 0;
  std::vector<double> values;  // its perturbation values (CampaignSpec::perturbations' order)
  std::string base_name, preset, strategy;
  std::uint64_t seed = 0;
  std::string status;  // "exit 0", "exit 1", "exit 2", "signal N"
  std::vector<std::pair<std::string, std::string>> fields;

  // The summary field `key` ("" when absent or null).
  const std::string& field(const std::string& key) const;
  bool passed() const { return status == "exit 0"; }
  bool failed() const { return status == "exit 1"; }  // ran, missed its expectations
};

struct ResultsTable {
  bool ok = false;
  std::vector<RunRow> rows;          // finished variants, by index
  std::vector<std::string> columns;  // summary fields, in first-seen order
  std::uint64_t missing = 0;         // variants not finished yet
  std::string error;                 // a summary that could not be read
};

// Reads every finished variant of the campaign in `out_dir`.
ResultsTable load_results(const CampaignSpec& spec, const std::string& out_dir);
// The CSV text of `t`.
std::string results_csv(const CampaignSpec& spec, const ResultsTable& t);

struct CollectResult {
  bool ok = false;
  std::uint64_t rows = 0;     // finished variants written
  std::uint64_t missing = 0;  // variants not finished yet
  std::string error;
};

// Writes OUT/results.csv whole (a temporary file, then rename).
CollectResult collect_results(const CampaignSpec& spec, const std::string& out_dir);

}  // namespace carril::sim::campaign
