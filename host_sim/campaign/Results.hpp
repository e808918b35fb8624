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

struct CollectResult {
  bool ok = false;
  std::uint64_t rows = 0;     // finished variants written
  std::uint64_t missing = 0;  // variants not finished yet
  std::string error;
};

// Writes OUT/results.csv whole (a temporary file, then rename).
CollectResult collect_results(const CampaignSpec& spec, const std::string& out_dir);

}  // namespace carril::sim::campaign
