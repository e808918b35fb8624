#include "host_sim/campaign/Slurm.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host_sim/campaign/Runner.hpp"
#include "loader/AtomicWrite.hpp"

extern char** environ;

namespace carril::sim::campaign {

namespace {
namespace fs = std::filesystem;

// Single quotes for the shell.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q.push_back(c);
    }
  }
  return q + "'";
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

// Runs argv with stdout and stderr into files; the exit status, or -1 with `error`.
int run_command(const std::vector<std::string>& args, const std::string& out,
                const std::string& err, std::string& error) {
  std::vector<std::string> a = args;
  std::vector<char*> argv;
  for (std::string& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, a[0].c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    error = a[0] + ": cannot start: " + std::strerror(rc);
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      error = a[0] + ": " + std::strerror(errno);
      return -1;
    }
  }
  if (!WIFEXITED(status)) {
    error = a[0] + ": killed by signal " + std::to_string(WTERMSIG(status));
    return -1;
  }
  return WEXITSTATUS(status);
}
}  // namespace

std::string array_list(const std::vector<std::uint64_t>& chunks) {
  std::string s;
  for (std::size_t i = 0; i < chunks.size();) {
    std::size_t j = i;
    while (j + 1 < chunks.size() && chunks[j + 1] == chunks[j] + 1) ++j;
    if (!s.empty()) s.push_back(',');
    s += std::to_string(chunks[i]);
    if (j > i) s += "-" + std::to_string(chunks[j]);
    i = j + 1;
  }
  return s;
}

std::vector<std::uint64_t> chunk_variants(const CampaignSpec& spec, std::uint64_t chunk_size,
                                          std::uint64_t chunk) {
  std::vector<std::uint64_t> v;
  const std::uint64_t n = spec.variant_count();
  for (std::uint64_t i = chunk * chunk_size; i < n && i < (chunk + 1) * chunk_size; ++i) {
    v.push_back(i);
  }
  return v;
}

std::vector<std::uint64_t> unfinished_chunks(const CampaignSpec& spec, const SlurmOptions& opt) {
  std::vector<std::uint64_t> chunks;
  const std::uint64_t k = opt.chunk_size == 0 ? 1 : opt.chunk_size;
  for (std::uint64_t i = 0; i < spec.variant_count(); ++i) {
    if (!variant_status(opt.out_dir, i).empty()) continue;
    if (chunks.empty() || chunks.back() != i / k) chunks.push_back(i / k);
  }
  return chunks;
}

std::string job_script(const CampaignSpec& spec, const SlurmOptions& opt,
                       const std::vector<std::uint64_t>& chunks) {
  const fs::path logs = fs::path(opt.out_dir) / "slurm";
  std::string s = "#!/bin/bash\n";
  s += "# carril campaign " + spec.name + ": " + std::to_string(chunks.size()) +
       " array tasks of up to " + std::to_string(opt.chunk_size) + " variants each.\n";
  s += "#SBATCH --job-name=carril-" + spec.name + "\n";
  s += "#SBATCH --array=" + array_list(chunks) + "\n";
  s += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n";
  s += "#SBATCH --output=" + (logs / "task-%A_%a.log").string() + "\n";
  if (!opt.partition.empty()) s += "#SBATCH --partition=" + opt.partition + "\n";
  s += "exec " + shell_quote(opt.campaign_exe) + " work " + shell_quote(opt.campaign_file) +
       " --out " + shell_quote(opt.out_dir) + " --sim " + shell_quote(opt.sim_path) +
       " --chunk-size " + std::to_string(opt.chunk_size) + " --chunk \"$SLURM_ARRAY_TASK_ID\"\n";
  return s;
}

SubmitResult submit_to_slurm(const CampaignSpec& spec, const SlurmOptions& opt) {
  SubmitResult r;
  const std::vector<std::uint64_t> chunks = unfinished_chunks(spec, opt);
  if (chunks.empty()) {
    r.ok = true;
    return r;
  }
  const fs::path dir = fs::path(opt.out_dir) / "slurm";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    r.error = dir.string() + ": cannot create: " + ec.message();
    return r;
  }
  const std::string script = (dir / "job.sh").string();
  if (auto e = loader::write_file_atomically(script, job_script(spec, opt, chunks))) {
    r.error = *e;
    return r;
  }
  const std::string out = (dir / "sbatch.out").string(), err = (dir / "sbatch.err").string();
  const int rc = run_command({opt.sbatch, "--parsable", script}, out, err, r.error);
  if (rc < 0) return r;
  const std::string said = trimmed(read_text(err));
  if (rc != 0) {
    r.error = opt.sbatch + " refused the job (exit " + std::to_string(rc) +
              "): " + (said.empty() ? trimmed(read_text(out)) : said) + "; nothing was submitted";
    return r;
  }
  // --parsable prints "jobid" or "jobid;cluster".
  std::string id = trimmed(read_text(out));
  if (const std::size_t semi = id.find(';'); semi != std::string::npos) id.resize(semi);
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    r.error = opt.sbatch + ": expected a job id from --parsable, got \"" + id + "\"";
    return r;
  }
  if (auto e = loader::write_file_atomically((dir / "job_id").string(), id + "\n")) {
    r.error = *e;
    return r;
  }
  r.ok = true;
  r.job_id = id;
  r.tasks = chunks.size();
  return r;
}

}  // namespace carril::sim::campaign
