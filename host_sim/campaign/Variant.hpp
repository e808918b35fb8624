#pragma once
// One run of a campaign: which base scenario, robot preset and strategy, the simulator's seed
// and the perturbation values, all derived from (campaign, index) alone, so any run can be made
// again from those two; and the scenario file it runs, written out whole next to its results.
#include <cstdint>
#include <string>
#include <vector>

#include "host_sim/campaign/CampaignFile.hpp"

namespace carril::sim::campaign {

struct Variant {
  std::uint64_t index = 0;
  std::size_t scenario = 0;  // into CampaignSpec::scenarios
  std::string base_name;     // the base scenario's name (its file name without .yaml)
  std::string preset;        // empty: the base scenario's own
  std::string strategy;      // empty: the base scenario's own
  std::uint64_t seed = 0;    // the simulator's seed for this run (< 2^53)
  // One value per CampaignSpec::perturbations entry, in that order.
  std::vector<double> values;
};

// Variant `index` (< spec.variant_count()) of the campaign. Its draws come from a counter-based
// generator keyed by (seed, index, perturbation key): the same on every machine and compiler, and
// one perturbation's values do not change when another is added.
Variant make_variant(const CampaignSpec& spec, std::uint64_t index);

struct ScenarioText {
  bool ok = false;
  std::string text;   // the variant's scenario file
  std::string error;  // names the base file and what could not be applied
};

// The base scenario with the variant applied: seed, robot.preset, mission.strategy, the
// perturbations, and a `map` made absolute (the variant's file lives in another folder). A
// comment at its top says which campaign, index and values it comes from.
ScenarioText variant_scenario(const CampaignSpec& spec, const Variant& v);

// A uniform double in [0, 1) from the 64-bit key (splitmix64's finaliser): the generator above.
double unit_draw(std::uint64_t key);
// The key of draw `k` of perturbation `name` for `index` of a campaign seeded `seed`.
std::uint64_t draw_key(std::uint64_t seed, std::uint64_t index, const std::string& name,
                       std::uint64_t k);

}  // namespace carril::sim::campaign
