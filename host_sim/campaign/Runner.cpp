#include "host_sim/campaign/Runner.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
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

// SIGINT, SIGTERM and SIGHUP (a closed terminal) set g_stop (no SA_RESTART: waitpid returns
// EINTR); restored on destruction.
class StopSignals {
 public:
  StopSignals() {
    g_stop.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    for (std::size_t i = 0; i < kSignals.size(); ++i) sigaction(kSignals[i], &sa, &old_[i]);
  }
  ~StopSignals() {
    for (std::size_t i = 0; i < kSignals.size(); ++i) sigaction(kSignals[i], &old_[i], nullptr);
  }

 private:
  static constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};
  std::array<struct sigaction, 3> old_{};
};

// OUT/.lock, held with flock() for the runner's life: a second runner on the same folder is
// refused (exclusive for a local run, shared among a Slurm array's tasks). The kernel drops it
// when the process dies, however it dies: no stale lock after a kill -9.
class FolderLock {
 public:
  bool take(const std::string& out_dir, bool shared, std::string& error) {
    const std::string path = (fs::path(out_dir) / ".lock").string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd_ < 0) {
      error = path + ": cannot open the folder's lock: " + std::strerror(errno);
      return false;
    }
    if (::flock(fd_, (shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
      error = out_dir + ": another carril_campaign is running on this folder (" + path +
              " is locked); wait for it or stop it first";
      return false;
    }
    return true;
  }
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);
  }

 private:
  int fd_ = -1;
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
// terminal reaches the runner alone, which stops its children itself). The child dies with the
// runner (PR_SET_PDEATHSIG): a runner killed with SIGKILL leaves no simulator behind to write
// into the folders a resumed campaign is using. -1 with `error` on failure.
pid_t spawn_sim(const RunnerOptions& opt, const fs::path& dir, std::string& error) {
  const std::string scenario = (dir / "scenario.yaml").string();
  const std::string out = (dir / "sim").string();
  const std::string log = (dir / "sim.log").string();
  std::vector<std::string> args = {opt.sim_path, "--scenario", scenario,    "--out",
                                   out,          "--quiet",    "--no-plots"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  int report[2];  // the child writes errno here when exec fails; closed on exec
  if (::pipe2(report, O_CLOEXEC) != 0) {
    error = opt.sim_path + ": cannot start: " + std::strerror(errno);
    return -1;
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    error = opt.sim_path + ": cannot start: " + std::strerror(errno);
    ::close(report[0]);
    ::close(report[1]);
    return -1;
  }
  if (pid == 0) {
    // The child: async-signal-safe calls only until exec.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the runner died before prctl took effect
    ::setpgid(0, 0);
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    for (int sig = 1; sig < NSIG; ++sig) ::sigaction(sig, &dfl, nullptr);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0 || ::dup2(fd, STDOUT_FILENO) < 0 || ::dup2(fd, STDERR_FILENO) < 0) {
      const int err = errno;
      (void)!::write(report[1], &err, sizeof err);
      ::_exit(127);
    }
    ::execve(opt.sim_path.c_str(), argv.data(), environ);
    const int err = errno;
    (void)!::write(report[1], &err, sizeof err);
    ::_exit(127);
  }
  ::close(report[1]);
  int err = 0;
  ssize_t n = 0;
  do {
    n = ::read(report[0], &err, sizeof err);
  } while (n < 0 && errno == EINTR);
  ::close(report[0]);
  if (n == static_cast<ssize_t>(sizeof err)) {
    ::waitpid(pid, nullptr, 0);
    error = opt.sim_path + ": cannot start: " + std::strerror(err);
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
  // Before the statuses are read: what another runner is writing is not this one's to judge.
  FolderLock lock;
  if (!lock.take(opt.out_dir, opt.shared_lock, c.error)) return c;
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
