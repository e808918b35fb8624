// carril_campaign: randomized scenario campaigns on this machine's cores or a Slurm cluster
// (docs/campaigns.md).
//   carril_campaign run FILE [--out DIR] [--jobs N]   run (or resume) every variant, then collect
//   carril_campaign run FILE --slurm [--chunk-size K] submit the unfinished ones as a job array
//   carril_campaign status FILE [--out DIR]           how many are finished, passed, failed
//   carril_campaign collect FILE [--out DIR]          write DIR/results.csv and DIR/report.md
//   carril_campaign work FILE --out DIR --chunk-size K --chunk C   one array task's variants
// Exit status: 0 every variant finished (passing or not), 1 some simulator refused its input or
// crashed, 2 bad input or the campaign could not be run, 130 interrupted (run it again to resume).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "host_sim/campaign/CampaignFile.hpp"
#include "host_sim/campaign/Report.hpp"
#include "host_sim/campaign/Results.hpp"
#include "host_sim/campaign/Runner.hpp"
#include "host_sim/campaign/Slurm.hpp"
#include "loader/AtomicWrite.hpp"
#include "loader/StrictYaml.hpp"

namespace {
namespace fs = std::filesystem;
using namespace carril::sim::campaign;

fs::path self_exe() {
  std::error_code ec;
  return fs::read_symlink("/proc/self/exe", ec);
}

// carril_sim beside this build's carril_campaign (host_sim/app/), unless $CARRIL_SIM says.
std::string default_sim() {
  if (const char* e = std::getenv("CARRIL_SIM")) return e;
  const fs::path self = self_exe();
  if (self.empty()) return "carril_sim";
  return (self.parent_path().parent_path() / "app" / "carril_sim").string();
}

std::string absolute(const std::string& p) {
  std::error_code ec;
  return fs::absolute(p, ec).lexically_normal().string();
}

// What Slurm says of the job array in OUT/slurm/job_id, best effort: "" when there is none.
std::string slurm_state(const std::string& out) {
  std::ifstream in(fs::path(out) / "slurm" / "job_id");
  std::string id;
  if (!(in >> id)) return "";
  const std::string cmd = "squeue -h -r -j " + id + " -o %T 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return "slurm job " + id + ": squeue could not be run";
  std::map<std::string, int> states;
  char line[256];
  std::string said;
  while (std::fgets(line, sizeof line, p) != nullptr) {
    std::string s(line);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    if (s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ_") == std::string::npos && !s.empty()) {
      ++states[s];
    } else {
      said += s;
    }
  }
  const int rc = ::pclose(p);
  if (rc != 0) return "slurm job " + id + ": squeue: " + said;
  if (states.empty()) return "slurm job " + id + ": no task left in the queue";
  std::string r = "slurm job " + id + ":";
  for (const auto& [state, n] : states) r += " " + std::to_string(n) + " " + state;
  return r;
}

struct Counts {
  std::uint64_t done = 0, passed = 0, failed = 0, errors = 0;
};

Counts count(const CampaignSpec& spec, const std::string& out) {
  Counts c;
  for (std::uint64_t i = 0; i < spec.variant_count(); ++i) {
    const std::string s = variant_status(out, i);
    if (s.empty()) continue;
    ++c.done;
    if (s == "exit 0") {
      ++c.passed;
    } else if (s == "exit 1") {
      ++c.failed;
    } else {
      ++c.errors;
    }
  }
  return c;
}

void print_counts(const CampaignSpec& spec, const Counts& c) {
  std::printf(
      "carril_campaign: %s: %llu variants: %llu finished (%llu passed, %llu failed, %llu "
      "errors), %llu to run\n",
      spec.name.c_str(), static_cast<unsigned long long>(spec.variant_count()),
      static_cast<unsigned long long>(c.done), static_cast<unsigned long long>(c.passed),
      static_cast<unsigned long long>(c.failed), static_cast<unsigned long long>(c.errors),
      static_cast<unsigned long long>(spec.variant_count() - c.done));
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"carril_campaign: randomized scenario campaigns"};
  app.require_subcommand(1);
  std::string file, out, sim = default_sim();
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  bool quiet = false, slurm = false;
  SlurmOptions so;
  std::uint64_t chunk = 0;
  CLI::App* run = app.add_subcommand("run", "run (or resume) every variant, then collect");
  CLI::App* status = app.add_subcommand("status", "how many variants are finished");
  CLI::App* collect =
      app.add_subcommand("collect", "write OUT/results.csv and the report, OUT/report.md");
  CLI::App* work = app.add_subcommand("work", "run one chunk's variants (a Slurm array task)");
  for (CLI::App* sub : {run, status, collect, work}) {
    sub->add_option("file", file, "campaign file (YAML)")->required();
    sub->add_option("--out", out, "results folder (default: runs/campaigns/<name>)");
  }
  for (CLI::App* sub : {run, collect, work}) {
    sub->add_option("--sim", sim,
                    "the carril_sim executable (default: this build's, or $CARRIL_SIM)");
  }
  run->add_option("--jobs", jobs, "simulators at a time (default: this machine's cores)")
      ->check(CLI::Range(1u, 4096u));
  run->add_flag("--quiet", quiet, "no progress line");
  run->add_flag("--slurm", slurm, "submit the unfinished variants to Slurm as one job array");
  run->add_option("--partition", so.partition, "--slurm: the partition (default: the cluster's)");
  run->add_option("--sbatch", so.sbatch, "--slurm: the submit command (default: sbatch)");
  for (CLI::App* sub : {run, work}) {
    sub->add_option("--chunk-size", so.chunk_size, "--slurm: variants per array task (10)")
        ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1000000)));
  }
  work->add_option("--chunk", chunk, "the chunk to run (a Slurm array task id)")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  const CampaignLoad load = load_campaign(file);
  if (!load.ok) {
    std::fprintf(stderr, "carril_campaign: %s\n", load.error.c_str());
    return 2;
  }
  const CampaignSpec& spec = load.spec;
  if (out.empty()) out = (fs::path("runs") / "campaigns" / spec.name).string();

  if (status->parsed()) {
    print_counts(spec, count(spec, out));
    const std::string s = slurm_state(out);
    if (!s.empty()) std::printf("carril_campaign: %s\n", s.c_str());
    return 0;
  }
  if (run->parsed() || work->parsed()) {
    std::string error;
    if (!prepare_campaign_dir(spec, carril::loader::strict::read_file(file), out, error)) {
      std::fprintf(stderr, "carril_campaign: %s\n", error.c_str());
      return 2;
    }
    if (::access(sim.c_str(), X_OK) != 0) {
      std::fprintf(stderr, "carril_campaign: %s: not an executable carril_sim (give --sim)\n",
                   sim.c_str());
      return 2;
    }
    if (slurm) {
      so.campaign_file = absolute(file);
      so.out_dir = absolute(out);
      so.campaign_exe = self_exe().string();
      so.sim_path = absolute(sim);
      const SubmitResult r = submit_to_slurm(spec, so);
      if (!r.ok) {
        std::fprintf(stderr, "carril_campaign: %s\n", r.error.c_str());
        return 2;
      }
      if (r.job_id.empty()) {
        std::printf("carril_campaign: every variant has finished: nothing to submit\n");
      } else {
        std::printf(
            "carril_campaign: submitted slurm job %s: %llu array tasks of up to %llu variants\n"
            "carril_campaign: follow it with: %s status %s --out %s\n"
            "carril_campaign: gather it with: %s collect %s --out %s\n",
            r.job_id.c_str(), static_cast<unsigned long long>(r.tasks),
            static_cast<unsigned long long>(so.chunk_size), argv[0], file.c_str(), out.c_str(),
            argv[0], file.c_str(), out.c_str());
      }
      return 0;
    }
    std::vector<std::uint64_t> pending;
    if (work->parsed()) {
      pending = chunk_variants(spec, so.chunk_size, chunk);
    } else {
      pending.resize(spec.variant_count());
      for (std::uint64_t i = 0; i < pending.size(); ++i) pending[i] = i;
    }
    RunnerOptions opt;
    opt.out_dir = out;
    opt.sim_path = sim;
    opt.jobs = work->parsed() ? 1 : jobs;
    opt.progress = !quiet && !work->parsed();
    opt.progress_tty = ::isatty(STDERR_FILENO) != 0;
    opt.shared_lock = work->parsed();
    const RunCounts c = run_variants(spec, pending, opt);
    if (!c.error.empty()) {
      std::fprintf(stderr, "carril_campaign: %s\n", c.error.c_str());
      return 2;
    }
    std::printf("carril_campaign: ran %llu variants now, %llu had finished before\n",
                static_cast<unsigned long long>(c.ran), static_cast<unsigned long long>(c.skipped));
    if (c.interrupted) {
      print_counts(spec, count(spec, out));
      std::printf("carril_campaign: interrupted; run the same command again to resume\n");
      return 130;
    }
    if (work->parsed()) return c.errors > 0 ? 1 : 0;
  }
  const ResultsTable table = load_results(spec, out);
  if (!table.ok) {
    std::fprintf(stderr, "carril_campaign: %s\n", table.error.c_str());
    return 2;
  }
  if (auto e = carril::loader::write_file_atomically((fs::path(out) / "results.csv").string(),
                                                     results_csv(spec, table))) {
    std::fprintf(stderr, "carril_campaign: %s\n", e->c_str());
    return 2;
  }
  const ReportResult rep = write_report(spec, table, absolute(out), absolute(sim));
  if (!rep.ok) {
    std::fprintf(stderr, "carril_campaign: the report: %s\n", rep.error.c_str());
    return 2;
  }
  const Counts c = count(spec, out);
  print_counts(spec, c);
  std::printf("carril_campaign: wrote %s/results.csv (%llu rows) and %s/report.md\n", out.c_str(),
              static_cast<unsigned long long>(table.rows.size()), out.c_str());
  return c.errors > 0 ? 1 : 0;
}
