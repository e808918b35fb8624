// The Slurm submission's pieces: the --array list, chunks, the unfinished chunks of a half-done
// campaign, and a job script that quotes paths for the shell.
#include "host_sim/campaign/Slurm.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "host_sim/campaign/Runner.hpp"

namespace carril::sim::campaign {
namespace {
namespace fs = std::filesystem;

CampaignSpec spec_with(std::uint32_t variants) {
  CampaignSpec s;
  s.name = "t";
  s.scenarios = {"a.yaml"};
  s.variants = variants;
  return s;
}

TEST(SlurmTest, TheArrayListJoinsRuns) {
  EXPECT_EQ(array_list({}), "");
  EXPECT_EQ(array_list({4}), "4");
  EXPECT_EQ(array_list({0, 1, 2, 3}), "0-3");
  EXPECT_EQ(array_list({0, 1, 2, 3, 7, 9, 10}), "0-3,7,9-10");
}

TEST(SlurmTest, ChunksCoverEveryVariantOnce) {
  const CampaignSpec s = spec_with(10);
  EXPECT_EQ(chunk_variants(s, 4, 0), (std::vector<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(chunk_variants(s, 4, 2), (std::vector<std::uint64_t>{8, 9}));
  EXPECT_TRUE(chunk_variants(s, 4, 3).empty());
}

TEST(SlurmTest, OnlyChunksWithUnfinishedVariantsAreSubmitted) {
  const fs::path dir =
      fs::temp_directory_path() / ("carril_slurm_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  SlurmOptions opt;
  opt.out_dir = dir.string();
  opt.chunk_size = 3;
  const CampaignSpec s = spec_with(10);
  EXPECT_EQ(unfinished_chunks(s, opt), (std::vector<std::uint64_t>{0, 1, 2, 3}));
  // Variants 0-5 and 9 finished: chunks 0 and 1 are done, 2 (6-8) is not, 3 (9) is.
  for (std::uint64_t i : {0u, 1u, 2u, 3u, 4u, 5u, 9u}) {
    fs::create_directories(variant_dir(opt.out_dir, i));
    std::ofstream(fs::path(variant_dir(opt.out_dir, i)) / "status") << "exit 0\n";
  }
  EXPECT_EQ(unfinished_chunks(s, opt), (std::vector<std::uint64_t>{2}));
  fs::remove_all(dir);
}

TEST(SlurmTest, TheJobScriptRunsOneChunkPerTaskWithQuotedPaths) {
  SlurmOptions opt;
  opt.campaign_file = "/data/it's here/c.yaml";
  opt.out_dir = "/shared/out";
  opt.campaign_exe = "/opt/carril/carril_campaign";
  opt.sim_path = "/opt/carril/carril_sim";
  opt.partition = "short";
  opt.chunk_size = 25;
  const std::string s = job_script(spec_with(100), opt, {0, 1, 3});
  EXPECT_NE(s.find("#SBATCH --array=0-1,3\n"), std::string::npos) << s;
  EXPECT_NE(s.find("#SBATCH --partition=short\n"), std::string::npos) << s;
  EXPECT_NE(s.find("#SBATCH --output=/shared/out/slurm/task-%A_%a.log\n"), std::string::npos) << s;
  EXPECT_NE(s.find("exec '/opt/carril/carril_campaign' work '/data/it'\\''s here/c.yaml' --out "
                   "'/shared/out' --sim '/opt/carril/carril_sim' --chunk-size 25 --chunk "
                   "\"$SLURM_ARRAY_TASK_ID\"\n"),
            std::string::npos)
      << s;
}

}  // namespace
}  // namespace carril::sim::campaign
