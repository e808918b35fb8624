#pragma once
// A campaign on a Slurm cluster: the unfinished variants in chunks of chunk_size, one job array
// task per chunk that holds any (sbatch --array=0-3,7,...), each task running
//   carril_campaign work FILE --out OUT --chunk-size K   (the chunk from $SLURM_ARRAY_TASK_ID)
// which runs its chunk's unfinished variants one after the other into OUT, a folder every node
// sees. Results are gathered from OUT by `carril_campaign status` / `collect`, as for a local run;
// a task that dies leaves its unfinished variants without a status, for the next run or
// submission.
#include <cstdint>
#include <string>
#include <vector>

#include "host_sim/campaign/CampaignFile.hpp"

namespace carril::sim::campaign {

struct SlurmOptions {
  std::string campaign_file;      // absolute
  std::string out_dir;            // absolute, shared by the nodes
  std::string campaign_exe;       // this carril_campaign, absolute
  std::string sim_path;           // carril_sim, absolute
  std::string sbatch = "sbatch";  // the submit command
  std::string partition;          // "" : the cluster's default
  std::uint64_t chunk_size = 10;  // variants per array task
};

// Slurm's --array list of the chunks: "0-3,7,9-10" (sorted, runs of consecutive ids as ranges).
std::string array_list(const std::vector<std::uint64_t>& chunks);

// The chunks (index / chunk_size) holding an unfinished variant of the campaign in opt.out_dir.
std::vector<std::uint64_t> unfinished_chunks(const CampaignSpec& spec, const SlurmOptions& opt);

// The batch script of the job array over `chunks`.
std::string job_script(const CampaignSpec& spec, const SlurmOptions& opt,
                       const std::vector<std::uint64_t>& chunks);

struct SubmitResult {
  bool ok = false;
  std::string job_id;       // as sbatch --parsable printed it
  std::uint64_t tasks = 0;  // array tasks submitted
  std::string error;        // names the command and what it said
};

// Writes OUT/slurm/job.sh and submits it; on success writes OUT/slurm/job_id. Nothing to run:
// ok with no job.
SubmitResult submit_to_slurm(const CampaignSpec& spec, const SlurmOptions& opt);

// The variant indices of chunk `chunk`.
std::vector<std::uint64_t> chunk_variants(const CampaignSpec& spec, std::uint64_t chunk_size,
                                          std::uint64_t chunk);

}  // namespace carril::sim::campaign
