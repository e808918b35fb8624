#pragma once
// A campaign's report, from its finished variants: OUT/report.md and plots in OUT/report/.
//   - the pass rate overall and per base scenario and robot/strategy pair, each with its 95 %
//     Wilson score interval;
//   - failure modes: the runs that did not pass, by how they ended (result, final state, fault)
//     and the first expectation they missed;
//   - metric distributions (cross-track RMS, stop error, time): median, 90th percentile and
//     maximum per pair, and a histogram of each;
//   - per perturbation, the pass rate over five bins of its values (a plot each), the
//     perturbations ranked by how far their worst bin falls below the overall rate;
//   - the ten worst runs, each with the one command that replays it in the viewer.
// Every file is written whole (a temporary file, then rename).
#include <string>

#include "host_sim/campaign/CampaignFile.hpp"
#include "host_sim/campaign/Results.hpp"

namespace carril::sim::campaign {

// A proportion's 95 % Wilson score interval for k successes in n trials (0, 0 when n = 0).
struct Interval {
  double lo = 0.0, hi = 0.0;
};
Interval wilson95(std::uint64_t k, std::uint64_t n);

struct ReportResult {
  bool ok = false;
  std::string error;
};

// `sim_command` is how the report tells to replay a run (e.g. "carril_sim").
ReportResult write_report(const CampaignSpec& spec, const ResultsTable& t,
                          const std::string& out_dir, const std::string& sim_command);

// The report's Markdown alone (no files written): for tests.
std::string report_markdown(const CampaignSpec& spec, const ResultsTable& t,
                            const std::string& out_dir, const std::string& sim_command);

}  // namespace carril::sim::campaign
