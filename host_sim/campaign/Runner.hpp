#pragma once
// Runs a campaign's variants as carril_sim processes, several at a time, into one output folder:
//
//   OUT/campaign.yaml        the campaign file as it was run (a resume must bring the same one)
//   OUT/runs/NNNNNN/         variant NNNNNN: scenario.yaml (what it ran), sim.log (the
//                            simulator's output), sim/ (its outputs: summary.json, plots) and
//                            status, written whole when the process has ended: "exit 0"
//                            (passed), "exit 1" (ran, expectations not met), "exit 2" (the
//                            simulator refused its input), "signal N" (it crashed)
//
// A variant with a status file is finished and never run again; one without (the campaign was
// interrupted, or a worker died) is cleared and run again on the next call. Ctrl-C (SIGINT or
// SIGTERM) stops the running simulators, writes no status for them and returns Interrupted.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host_sim/campaign/CampaignFile.hpp"

namespace carril::sim::campaign {

struct RunnerOptions {
  std::string out_dir;        // OUT
  std::string sim_path;       // the carril_sim executable
  unsigned jobs = 1;          // simulators at a time
  bool progress = true;       // a progress line on stderr
  bool progress_tty = false;  // redraw it in place (a terminal) or print a line every 5 s
  bool shared_lock = false;   // a Slurm array task: shares OUT's lock with the other tasks (a
                              // local run holds it alone, so the two never run side by side)
};

struct RunCounts {
  std::uint64_t total = 0;                           // variants asked for
  std::uint64_t skipped = 0;                         // finished by an earlier call
  std::uint64_t ran = 0;                             // finished by this call
  std::uint64_t passed = 0, failed = 0, errors = 0;  // of those finished by this call
  bool interrupted = false;
  std::string error;  // set when the campaign could not be run at all
};

// A whole file's bytes; "" when it cannot be read (a status or job file not written yet).
std::string read_text(const std::string& path);
// The status of variant `index` in `out_dir`: "" when it has not finished.
std::string variant_status(const std::string& out_dir, std::uint64_t index);
// OUT/runs/NNNNNN
std::string variant_dir(const std::string& out_dir, std::uint64_t index);

// Checks OUT against the campaign (a new folder, or one holding the same campaign text) and
// writes OUT/campaign.yaml. false with `error` naming the folder otherwise.
bool prepare_campaign_dir(const CampaignSpec& spec, const std::string& campaign_text,
                          const std::string& out_dir, std::string& error);

// Runs the unfinished variants among `indices`.
RunCounts run_variants(const CampaignSpec& spec, const std::vector<std::uint64_t>& indices,
                       const RunnerOptions& opt);

}  // namespace carril::sim::campaign
