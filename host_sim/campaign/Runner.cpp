#include "host_sim/campaign/Runner.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "host_sim/campaign/Variant.hpp"
#include "loader/AtomicWrite.hpp"

extern char** environ;

namespace carril::sim::campaign {

namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_stop{0};
extern "C" void on_stop_signal(int sig) {
  g_stop.store(sig);
}

// SIGINT/SIGTERM set g_stop (no SA_RESTART: waitpid returns EINTR); restored on destruction.
class StopSignals {
 public:
  StopSignals() {
    g_stop.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

std::string duration_text(double s) {
  char buf[32];
  if (s >= 3600.0) {
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600.0), int(std::fmod(s, 3600.0) / 60.0));
  } else {
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60.0), int(std::fmod(s, 60.0)));
  }
  return buf;
}

// Starts carril_sim on the variant's scenario in its own process group (a Ctrl-C at the
// terminal reaches the runner alone, which stops its children itself). -1 with `error` on failure.
pid_t spawn_sim(const RunnerOptions& opt, const fs::path& dir, std::string& error) {
  const std::string scenario = (dir / "scenario.yaml").string();
  const std::string out = (dir / "sim").string();
  const std::string log = (dir / "sim.log").string();
  std::vector<std::string> args = {opt.sim_path, "--scenario", scenario,    "--out",
                                   out,          "--quiet",    "--no-plots"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_init(&attr);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, opt.sim_path.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    error = opt.sim_path + ": cannot start: " + std::strerror(rc);
    return -1;
  }
  return pid;
}

class Progress {
 public:
  Progress(const RunnerOptions& opt, std::uint64_t pending) : opt_(opt), pending_(pending) {}
  void update(const RunCounts& c, bool last) {
    if (!opt_.progress) return;
    const auto now = Clock::now();
    if (!last && !opt_.progress_tty && now - printed_ < std::chrono::seconds(5)) return;
    printed_ = now;
    const double wall = std::chrono::duration<double>(now - t0_).count();
    const double rate = wall > 0.0 ? double(c.ran) / wall : 0.0;
    const double left = rate > 0.0 ? double(pending_ - c.ran) / rate : 0.0;
    const int width = 30;
    const int fill = pending_ == 0 ? width : int(double(width) * double(c.ran) / double(pending_));
    std::string bar(std::size_t(fill), '#');
    bar.resize(std::size_t(width), '.');
    std::fprintf(stderr, "%s[%s] %llu/%llu done, %llu failed, %llu errors, %.2f runs/s, %s left%s",
                 opt_.progress_tty ? "\r" : "", bar.c_str(),
                 static_cast<unsigned long long>(c.skipped + c.ran),
                 static_cast<unsigned long long>(c.total),
                 static_cast<unsigned long long>(c.failed),
                 static_cast<unsigned long long>(c.errors), rate, duration_text(left).c_str(),
                 opt_.progress_tty && !last ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  const RunnerOptions& opt_;
  std::uint64_t pending_;
  Clock::time_point t0_ = Clock::now();
  Clock::time_point printed_{};
};
}  // namespace

std::string variant_dir(const std::string& out_dir, std::uint64_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%06llu", static_cast<unsigned long long>(index));
  return (fs::path(out_dir) / "runs" / name).string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string variant_status(const std::string& out_dir, std::uint64_t index) {
  std::string s = read_text(fs::path(variant_dir(out_dir, index)) / "status");
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

bool prepare_campaign_dir(const CampaignSpec& spec, const std::string& campaign_text,
                          const std::string& out_dir, std::string& error) {
  std::error_code ec;
  const fs::path copy = fs::path(out_dir) / "campaign.yaml";
  if (fs::exists(copy, ec)) {
    if (read_text(copy) != campaign_text) {
      error = out_dir + ": holds the results of another campaign (its campaign.yaml differs from " +
              spec.path + "); give a new --out folder, or the same campaign file to resume it";
      return false;
    }
    return true;
  }
  if (fs::exists(out_dir, ec) && !fs::is_empty(out_dir, ec)) {
    error = out_dir +
            ": exists and is not a campaign's folder (no campaign.yaml); give a new or "
            "empty folder";
    return false;
  }
  fs::create_directories(fs::path(out_dir) / "runs", ec);
  if (ec) {
    error = out_dir + ": cannot create: " + ec.message();
    return false;
  }
  if (auto e = loader::write_file_atomically(copy.string(), campaign_text)) {
    error = *e;
    return false;
  }
  return true;
}

RunCounts run_variants(const CampaignSpec& spec, const std::vector<std::uint64_t>& indices,
                       const RunnerOptions& opt) {
  RunCounts c;
  c.total = indices.size();
  std::vector<std::uint64_t> pending;
  for (const std::uint64_t i : indices) {
    if (variant_status(opt.out_dir, i).empty()) {
      pending.push_back(i);
    } else {
      ++c.skipped;
    }
  }
  StopSignals signals;
  Progress progress(opt, pending.size());
  std::map<pid_t, std::uint64_t> running;
  std::size_t next = 0;
  const unsigned jobs = opt.jobs == 0 ? 1 : opt.jobs;
  const auto start_one = [&]() -> bool {
    const std::uint64_t index = pending[next++];
    const fs::path dir = variant_dir(opt.out_dir, index);
    std::error_code ec;
    fs::remove_all(dir, ec);  // what an interrupted run left
    fs::create_directories(dir, ec);
    if (ec) {
      c.error = dir.string() + ": cannot create: " + ec.message();
      return false;
    }
    const ScenarioText s = variant_scenario(spec, make_variant(spec, index));
    if (!s.ok) {
      c.error = s.error;
      return false;
    }
    if (auto e = loader::write_file_atomically((dir / "scenario.yaml").string(), s.text)) {
      c.error = *e;
      return false;
    }
    const pid_t pid = spawn_sim(opt, dir, c.error);
    if (pid < 0) return false;
    running[pid] = index;
    return true;
  };
  bool ok = true;
  while (ok && g_stop.load() == 0 && next < pending.size() && running.size() < jobs)
    ok = start_one();
  bool stopping = false;
  while (!running.empty()) {
    if (!stopping && (g_stop.load() != 0 || !ok)) {
      stopping = true;
      for (const auto& [pid, index] : running) kill(pid, SIGTERM);
    }
    // Polled, not blocking: a stop request must not wait for a long run to end.
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid == 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::uint64_t index = it->second;
    running.erase(it);
    if (g_stop.load() != 0 || !ok) continue;  // stopped by us: no status, run again on resume
    std::string st;
    if (WIFEXITED(status)) {
      const int rc = WEXITSTATUS(status);
      st = "exit " + std::to_string(rc);
      if (rc == 0) {
        ++c.passed;
      } else if (rc == 1) {
        ++c.failed;
      } else {
        ++c.errors;
      }
    } else {
      st = "signal " + std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0);
      ++c.errors;
    }
    if (auto e = loader::write_file_atomically(
            (fs::path(variant_dir(opt.out_dir, index)) / "status").string(), st + "\n")) {
      c.error = *e;
      ok = false;
      continue;
    }
    ++c.ran;
    progress.update(c, false);
    while (ok && g_stop.load() == 0 && next < pending.size() && running.size() < jobs) {
      ok = start_one();
    }
  }
  c.interrupted = g_stop.load() != 0;
  progress.update(c, true);
  return c;
}

}  // namespace carril::sim::campaign
