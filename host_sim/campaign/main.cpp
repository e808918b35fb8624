// carril_campaign: randomized scenario campaigns on this machine's cores (docs/campaigns.md).
//   carril_campaign run FILE [--out DIR] [--jobs N]   run (or resume) every variant, then collect
//   carril_campaign status FILE [--out DIR]           how many are finished, passed, failed
//   carril_campaign collect FILE [--out DIR]          write DIR/results.csv and DIR/report.md
// Exit status: 0 every variant finished (passing or not), 1 some simulator refused its input or
// crashed, 2 bad input or the campaign could not be run, 130 interrupted (run it again to resume).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "host_sim/campaign/CampaignFile.hpp"
#include "host_sim/campaign/Report.hpp"
#include "host_sim/campaign/Results.hpp"
#include "host_sim/campaign/Runner.hpp"
#include "loader/AtomicWrite.hpp"
#include "loader/StrictYaml.hpp"

namespace {
namespace fs = std::filesystem;
using namespace carril::sim::campaign;

// carril_sim beside this build's carril_campaign (host_sim/app/), unless $CARRIL_SIM says.
std::string default_sim() {
  if (const char* e = std::getenv("CARRIL_SIM")) return e;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "carril_sim";
  return (self.parent_path().parent_path() / "app" / "carril_sim").string();
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
  bool quiet = false;
  CLI::App* run = app.add_subcommand("run", "run (or resume) every variant, then collect");
  CLI::App* status = app.add_subcommand("status", "how many variants are finished");
  CLI::App* collect =
      app.add_subcommand("collect", "write OUT/results.csv and the report, OUT/report.md");
  for (CLI::App* sub : {run, status, collect}) {
    sub->add_option("file", file, "campaign file (YAML)")->required();
    sub->add_option("--out", out, "results folder (default: runs/campaigns/<name>)");
  }
  run->add_option("--jobs", jobs, "simulators at a time (default: this machine's cores)")
      ->check(CLI::Range(1u, 4096u));
  run->add_option("--sim", sim,
                  "the carril_sim executable (default: this build's, or $CARRIL_SIM)");
  run->add_flag("--quiet", quiet, "no progress line");
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
    return 0;
  }
  if (run->parsed()) {
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
    std::vector<std::uint64_t> all(spec.variant_count());
    for (std::uint64_t i = 0; i < all.size(); ++i) all[i] = i;
    RunnerOptions opt;
    opt.out_dir = out;
    opt.sim_path = sim;
    opt.jobs = jobs;
    opt.progress = !quiet;
    opt.progress_tty = ::isatty(STDERR_FILENO) != 0;
    const RunCounts c = run_variants(spec, all, opt);
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
  std::error_code ec;
  const std::string sim_abs = fs::absolute(sim, ec).lexically_normal().string();
  const ReportResult rep = write_report(spec, table, fs::absolute(out, ec).string(), sim_abs);
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
