#pragma once
// Campaign files: a YAML file naming base scenarios, robot preset / strategy pairs, how many
// variants of each pair to run, and the perturbations each variant draws (docs/campaigns.md).
// Read strictly like scenario files: unknown, missing, mistyped and out-of-range keys, and
// distributions whose values could leave what the perturbed key accepts, are errors of the form
//   "<file>:<line>: <key.path>: expected <what>, got <what>".
#include <cstdint>
#include <string>
#include <vector>

namespace carril::sim::campaign {

// How a perturbation's value is drawn for each variant.
struct Distribution {
  enum class Kind : std::uint8_t { Fixed, Uniform, Normal };
  Kind kind = Kind::Fixed;
  double a = 0.0;  // Fixed: the value; Uniform: low; Normal: mean
  double b = 0.0;  // Uniform: high; Normal: standard deviation
  // Normal only: draws outside [clip_lo, clip_hi] are drawn again (a truncated normal).
  double clip_lo = 0.0, clip_hi = 0.0;
};

// A perturbation key the variants can draw, and the values the scenario format accepts for it.
struct PerturbationKind {
  const char* key;
  double lo, hi;     // accepted values
  const char* unit;  // for messages and the docs
  const char* what;  // one line: what it changes in the scenario
};
// Every key a campaign file may perturb, in the order the CSV lists them.
const std::vector<PerturbationKind>& perturbation_kinds();

struct Perturbation {
  std::string key;
  Distribution dist;
};

// A robot preset and the strategy it runs (robot.preset, mission.strategy).
struct RobotStrategy {
  std::string preset;
  std::string strategy;
};

struct CampaignSpec {
  std::string name;                    // [A-Za-z0-9_-], 1..64
  std::string path;                    // the campaign file, as given
  std::uint64_t seed = 0;              // every variant's draws derive from it and the index
  std::vector<std::string> scenarios;  // base scenario files, resolved against the file's folder
  std::vector<RobotStrategy> robots;   // empty: each scenario's own preset and strategy
  std::uint32_t variants = 1;          // per (scenario, robot) pair
  std::vector<Perturbation> perturbations;

  // Variants in all: scenarios x max(1, robots) x variants.
  std::uint64_t variant_count() const;
};

struct CampaignLoad {
  bool ok = false;
  CampaignSpec spec;
  std::string error;
};

CampaignLoad load_campaign(const std::string& path);
// Same, from text in memory; `path` names the file in messages and resolves the scenarios.
CampaignLoad load_campaign_text(const std::string& text, const std::string& path);

}  // namespace carril::sim::campaign
