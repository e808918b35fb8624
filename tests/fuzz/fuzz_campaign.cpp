// Fuzz target: campaign files (host_sim/campaign/CampaignFile), read as if they sat in
// scenarios/campaigns/ (so the seeds' relative scenario paths resolve), then the first and last
// variants drawn and the first one's scenario written. A crash, leak or UB report is a bug; a
// rejection must say why.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "host_sim/campaign/CampaignFile.hpp"
#include "host_sim/campaign/Variant.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace carril::sim::campaign;
  const std::string path = std::string(CARRIL_SOURCE_DIR) + "/scenarios/campaigns/fuzz.yaml";
  const CampaignLoad r = load_campaign_text(std::string(carril::fuzz::as_text(data, size)), path);
  carril::fuzz::print_outcome(r.ok, r.error);
  if (!r.ok) {
    if (r.error.empty()) std::abort();
    return 0;
  }
  const std::uint64_t n = r.spec.variant_count();
  if (n == 0) std::abort();  // a loaded campaign has at least one variant
  const Variant first = make_variant(r.spec, 0);
  const Variant last = make_variant(r.spec, n - 1);
  if (first.values.size() != r.spec.perturbations.size() ||
      last.scenario >= r.spec.scenarios.size()) {
    std::abort();
  }
  const ScenarioText t = variant_scenario(r.spec, first);
  if (!t.ok && t.error.empty()) std::abort();
  return 0;
}
