#include "host_sim/output/RunOutputs.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "host_sim/output/Json.hpp"
#include "host_sim/output/Plots.hpp"
#include "loader/AtomicWrite.hpp"

namespace carril::sim {
namespace {

std::string errno_text(int err) {
  return std::strerror(err);
}

// Fixed-point with `decimals` digits, locale-independent (printf honours LC_NUMERIC).
void append_fixed(std::string& out, double v, int decimals) {
  char buf[400];  // room for DBL_MAX in fixed notation
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  if (r.ec == std::errc()) out.append(buf, r.ptr);
}

// Best effort: makes the rename itself durable; a failure here loses nothing already written.
void fsync_dir(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

bool write_file_atomic(const std::string& path, const std::string& content, std::string& error) {
  // One atomic writer for the whole project: a fresh temporary (no symlink followed, no name
  // reused, the umask's mode), fsync, rename, fsync of the directory.
  if (const std::optional<std::string> e = loader::write_file_atomically(path, content)) {
    error = "cannot write " + *e;
    return false;
  }
  return true;
}

std::string summary_to_json(const RunSummary& s) {
  json::ObjectWriter w;
  // The contract's keys, in RunSummary's order; do not reorder or rename.
  w.str("scenario", s.scenario);
  w.str("result", s.result);
  w.boolean("passed", s.passed);
  w.num("sim_time_s", s.sim_time_s);
  w.num("wall_time_s", s.wall_time_s);
  w.num("real_time_factor", s.real_time_factor);
  w.integer("ticks", s.ticks);
  w.num("tick_period_s", s.tick_period_s);
  w.integer("tick_overruns", s.tick_overruns);
  w.num("tick_compute_p50_us", s.tick_compute_p50_us);
  w.num("tick_compute_p99_us", s.tick_compute_p99_us);
  w.num("tick_compute_max_us", s.tick_compute_max_us);
  w.integer("heap_allocations_after_init", s.heap_allocations_after_init);
  w.integer("collisions", s.collisions);
  w.integer("mover_contacts", s.mover_contacts);
  w.num("progress", s.progress);
  w.integer("laps", s.laps);
  w.num("cross_track_rms_m", s.cross_track_rms_m);
  w.num("cross_track_max_m", s.cross_track_max_m);
  w.integer("line_lost_events", s.line_lost_events);
  w.integer("line_reacquired_events", s.line_reacquired_events);
  w.integer("obstacles_avoided", s.obstacles_avoided);
  w.boolean("end_reached", s.end_reached);
  w.num("end_stop_error_m", s.end_stop_error_m);
  w.num("path_length_m", s.path_length_m);
  w.num("mean_speed_mps", s.mean_speed_mps);
  w.num("max_abs_wz_radps", s.max_abs_wz_radps);
  w.str("final_state", s.final_state);
  // Added keys.
  w.str_array("unmet_expectations", s.unmet_expectations);
  w.str_or_null("fault", s.fault);
  w.str("mission", s.mission);
  w.str("mission_status", s.mission_status);
  {
    json::ObjectWriter counters;
    for (const auto& [name, value] : s.mission_counters) counters.integer(name, value);
    w.raw("mission_counters", counters.finish_inline());
  }
  w.integer("task_overrun_events", s.task_overrun_events);
  w.integer("falls", s.falls);
  if (s.goal_reached) {
    w.boolean("goal_reached", *s.goal_reached);
  } else {
    w.raw("goal_reached", "null");
  }
  w.num("goal_error_m", s.goal_error_m);
  w.num("goal_yaw_error_deg", s.goal_yaw_error_deg);
  w.integer("replans", s.replans);
  w.integer("cells_checked", s.cells_checked);
  w.num("coverage", s.coverage);
  w.num("coverage_overlap", s.coverage_overlap);
  w.num("coverage_area_m2", s.coverage_area_m2);
  w.num("coverage_lower_bound_s", s.coverage_lower_bound_s);
  w.num("coverage_time_ratio", s.coverage_time_ratio);
  w.num("localisation_rmse_m", s.localisation_rmse_m);
  w.num("localisation_max_error_m", s.localisation_max_error_m);
  w.num("yaw_rmse_deg", s.yaw_rmse_deg);
  w.num("time_to_converge_s", s.time_to_converge_s);
  w.num("relocalised_after_kidnap_s", s.relocalised_after_kidnap_s);
  {
    std::string list = "[";
    for (std::size_t i = 0; i < s.relocalised_after_kidnaps_s.size(); ++i) {
      if (i > 0) list += ", ";
      list += json::number(s.relocalised_after_kidnaps_s[i]);
    }
    w.raw("relocalised_after_kidnaps_s", list + "]");
  }
  {
    json::ObjectWriter counters;
    for (const auto& [name, value] : s.localisation_counters) counters.integer(name, value);
    w.raw("localisation_counters", counters.finish_inline());
  }
  {
    json::ObjectWriter counters;
    for (const auto& [name, value] : s.safety_counters) counters.integer(name, value);
    counters.num("blocked_max_s", s.blocked_max_s);
    w.raw("safety_counters", counters.finish_inline());
  }
  {
    json::ObjectWriter tasks;
    for (const RunSummary::TaskTime& t : s.tasks) {
      json::ObjectWriter one;
      one.integer("runs", t.runs);
      one.integer("overruns", t.overruns);
      one.num("p50_us", t.p50_us);
      one.num("p99_us", t.p99_us);
      one.num("max_us", t.max_us);
      tasks.raw(t.name, one.finish_inline());
    }
    w.raw("tasks", tasks.finish_inline());
  }
  return w.finish();
}

std::string trajectory_to_csv(const std::vector<TrajectoryRow>& rows) {
  std::string out = "t,x,y,yaw,vx,vy,wz,state,cross_track_m\n";
  out.reserve(out.size() + rows.size() * 72);
  for (const TrajectoryRow& r : rows) {
    append_fixed(out, r.t, 3);
    for (const double v : {r.x, r.y, r.yaw, r.vx, r.vy, r.wz}) {
      out.push_back(',');
      append_fixed(out, v, 5);
    }
    out.push_back(',');
    out += r.state != nullptr ? r.state : "";
    out.push_back(',');
    append_fixed(out, r.cross_track_m, 5);
    out.push_back('\n');
  }
  return out;
}

namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 4> kOutputFiles = {"trajectory.csv", "trajectory.png",
                                                     "velocities.png", "summary.json"};
// What a run with a costmap adds (RunExtraFile names must be among these).
constexpr std::array<const char*, 7> kExtraOutputFiles = {
    "costmap.png",    "costmap.pgm",   "costmap.yaml", "traversability.png",
    "elevation.cmap", "obstacles.png", "coverage.png"};

std::string g_fault;  // set_output_fault_for_test

bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (const char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

// A previous run's file, or a per-file temporary ("<file>.tmp.<pid>") a cut-short write left.
bool is_output_name(std::string_view n) {
  std::array<std::string_view, kOutputFiles.size() + kExtraOutputFiles.size()> names{};
  std::size_t k = 0;
  for (const char* f : kOutputFiles) names[k++] = f;
  for (const char* f : kExtraOutputFiles) names[k++] = f;
  for (const std::string_view f : names) {
    if (n == f) return true;
    if (n.size() > f.size() + 5 && n.substr(0, f.size()) == f && n.substr(f.size(), 5) == ".tmp." &&
        all_digits(n.substr(f.size() + 5))) {
      return true;
    }
  }
  return false;
}

// Where the set lives and where it is staged; absolute, so the renames do not depend on the
// spelling of `dir` ("runs/x/", "./runs/x").
struct OutPaths {
  std::string shown;  // as the user gave it, for messages
  fs::path dir, parent, staging, aside;
  std::string name;
};

bool resolve(const std::string& dir, OutPaths& p, std::string& error) {
  p.shown = dir;
  if (dir.empty()) {
    error = "output directory: empty path";
    return false;
  }
  std::error_code ec;
  fs::path abs = fs::absolute(dir, ec);
  if (ec) {
    error = "output directory " + dir + ": " + ec.message();
    return false;
  }
  abs = abs.lexically_normal();
  if (!abs.has_filename()) abs = abs.parent_path();  // "runs/x/" names "runs/x"
  if (abs == abs.root_path() || abs.filename() == "." || abs.filename() == "..") {
    error = "output directory " + dir + ": cannot replace the filesystem root";
    return false;
  }
  p.dir = abs;
  p.parent = abs.parent_path();
  p.name = abs.filename().string();
  const std::string pid = std::to_string(::getpid());
  p.staging = p.parent / ("." + p.name + ".tmp." + pid);
  p.aside = p.parent / ("." + p.name + ".old." + pid);
  return true;
}

// `dir` is missing, or a directory with nothing but outputs in it.
bool check_replaceable(const OutPaths& p, std::string& error) {
  struct stat st {};
  if (::lstat(p.dir.c_str(), &st) != 0) {
    if (errno == ENOENT) return true;
    error = "output directory " + p.shown + ": " + errno_text(errno);
    return false;
  }
  if (S_ISLNK(st.st_mode)) {
    error = "output directory " + p.shown +
            " is a symbolic link; carril_sim replaces the whole directory, give the real path";
    return false;
  }
  if (!S_ISDIR(st.st_mode)) {
    error = "output directory " + p.shown + " exists and is not a directory";
    return false;
  }
  std::error_code ec;
  std::vector<std::string> foreign;
  for (fs::directory_iterator it(p.dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    std::error_code ec2;
    if (!is_output_name(n) || !it->is_regular_file(ec2) || it->is_symlink(ec2)) {
      foreign.push_back(n);
    }
  }
  if (ec) {
    error = "output directory " + p.shown + ": cannot list: " + ec.message();
    return false;
  }
  if (!foreign.empty()) {
    std::string names;
    for (std::size_t i = 0; i < foreign.size() && i < 3; ++i) {
      names += (i ? ", " : "") + foreign[i];
    }
    if (foreign.size() > 3) names += ", ...";
    error = "output directory " + p.shown + " holds files that are not a previous run's outputs (" +
            names +
            "); carril_sim replaces the whole directory, so give a new or empty directory or "
            "one it wrote before";
    return false;
  }
  return true;
}

// Only outputs in it (or empty): safe to delete.
bool holds_only_outputs(const fs::path& d) {
  std::error_code ec;
  for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code ec2;
    if (!is_output_name(it->path().filename().string()) || !it->is_regular_file(ec2) ||
        it->is_symlink(ec2)) {
      return false;
    }
  }
  return !ec;
}

// Staging and set-aside directories of runs that died before cleaning up (their pid is gone),
// or of this process: removed when they hold nothing but outputs. Best effort.
void remove_stale_staging(const OutPaths& p) {
  std::error_code ec;
  const std::string tmp_prefix = "." + p.name + ".tmp.", old_prefix = "." + p.name + ".old.";
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(p.parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    std::string_view pid;
    if (n.rfind(tmp_prefix, 0) == 0) {
      pid = std::string_view(n).substr(tmp_prefix.size());
    } else if (n.rfind(old_prefix, 0) == 0) {
      pid = std::string_view(n).substr(old_prefix.size());
    } else {
      continue;
    }
    if (!all_digits(pid) || pid.size() > 9) continue;
    const long id = std::stol(std::string(pid));
    const bool dead =
        id == ::getpid() || (::kill(static_cast<pid_t>(id), 0) != 0 && errno == ESRCH);
    std::error_code ec2;
    if (dead && it->is_directory(ec2) && !it->is_symlink(ec2) && holds_only_outputs(it->path())) {
      stale.push_back(it->path());
    }
  }
  for (const fs::path& d : stale) fs::remove_all(d, ec);
}

// A fresh, empty staging directory.
bool make_staging(const OutPaths& p, std::string& error) {
  if (::mkdir(p.staging.c_str(), 0755) == 0) return true;
  error = "cannot create staging directory " + p.staging.string() + ": " + errno_text(errno);
  return false;
}

bool create_parent(const OutPaths& p, std::string& error) {
  std::error_code ec;
  fs::create_directories(p.parent, ec);
  if (ec) {
    error = "cannot create directory " + p.parent.string() + " for output directory " + p.shown +
            ": " + ec.message();
    return false;
  }
  return true;
}

}  // namespace

void set_output_fault_for_test(const std::string& step) {
  g_fault = step;
}

bool prepare_output_dir(const std::string& dir, std::string& error) {
  OutPaths p;
  if (!resolve(dir, p, error) || !check_replaceable(p, error) || !create_parent(p, error)) {
    return false;
  }
  remove_stale_staging(p);
  if (!make_staging(p, error)) return false;
  const fs::path probe = p.staging / "probe";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = "cannot create a file in " + p.staging.string() + ": " + errno_text(errno);
    ::rmdir(p.staging.c_str());
    return false;
  }
  ::close(fd);
  bool ok = true;
  if (::unlink(probe.c_str()) != 0) {
    error = "cannot remove " + probe.string() + ": " + errno_text(errno);
    ok = false;
  }
  if (::rmdir(p.staging.c_str()) != 0 && ok) {
    error = "cannot remove " + p.staging.string() + ": " + errno_text(errno);
    ok = false;
  }
  return ok;
}

bool write_run_outputs(const std::string& dir, const Scenario& scenario,
                       const std::vector<TrajectoryRow>& rows,
                       const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                       std::string& error, const ExtraOutputs& extra, bool plots) {
  OutPaths p;
  // Checked again: the directory may have changed during the run, and it is about to be replaced.
  if (!resolve(dir, p, error) || !check_replaceable(p, error) || !create_parent(p, error)) {
    return false;
  }
  remove_stale_staging(p);
  if (!make_staging(p, error)) return false;
  auto abandon = [&](const std::string& why) {
    std::error_code ec;
    fs::remove_all(p.staging, ec);
    error = why;
    return false;
  };
  auto write = [&](const char* name, const std::string& content) {
    if (g_fault == name) {
      error = "cannot write " + (p.staging / name).string() + ": injected failure (test)";
      return false;
    }
    return write_file_atomic((p.staging / name).string(), content, error);
  };

  std::string png;
  if (!write("trajectory.csv", trajectory_to_csv(rows))) return abandon(error);
  if (plots) {
    if (!render_trajectory_png(scenario, rows, collisions, summary, png, error)) {
      return abandon(error);
    }
    if (!write("trajectory.png", png)) return abandon(error);
    if (!render_velocities_png(rows, summary, png, error)) return abandon(error);
    if (!write("velocities.png", png)) return abandon(error);
  }
  if (extra) {
    if (!extra(p.staging.string(), error)) return abandon(error);
    // Only the known names may join the set (a later run must recognise it as outputs).
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(p.staging, ec)) {
      const std::string n = e.path().filename().string();
      if (!is_output_name(n)) return abandon("internal: " + n + " is not a run output file");
    }
  }
  if (!write("summary.json", summary_to_json(summary))) return abandon(error);
  fsync_dir(p.staging);

  const std::string swap_what = "cannot move " + p.staging.string() + " to " + p.shown + ": ";
  if (g_fault == "swap") return abandon(swap_what + "injected failure (test)");
  struct stat st {};
  if (::lstat(p.dir.c_str(), &st) != 0) {
    // No previous set: the staging directory becomes the output directory.
    if (::rename(p.staging.c_str(), p.dir.c_str()) != 0)
      return abandon(swap_what + errno_text(errno));
    fsync_dir(p.parent);
    return true;
  }
  int rc = -1;
  int err = EINVAL;
  if (g_fault != "no_exchange") {
    rc = ::renameat2(AT_FDCWD, p.staging.c_str(), AT_FDCWD, p.dir.c_str(), RENAME_EXCHANGE);
    err = errno;
  }
  if (rc == 0) {
    // The staging directory now holds the previous set.
    fsync_dir(p.parent);
    std::error_code ec;
    fs::remove_all(p.staging, ec);
    return true;
  }
  if (err != EINVAL && err != ENOSYS && err != EOPNOTSUPP)
    return abandon(swap_what + errno_text(err));
  // No exchange on this filesystem: the previous set goes aside, the new one in, and the previous
  // one comes back if that fails. At every instant each set is whole under one of the names.
  if (::rename(p.dir.c_str(), p.aside.c_str()) != 0) {
    return abandon("cannot move " + p.shown + " aside to " + p.aside.string() + ": " +
                   errno_text(errno));
  }
  if (::rename(p.staging.c_str(), p.dir.c_str()) != 0) {
    const std::string why = swap_what + errno_text(errno);
    if (::rename(p.aside.c_str(), p.dir.c_str()) != 0) {
      return abandon(why + "; the previous outputs are in " + p.aside.string());
    }
    return abandon(why);
  }
  fsync_dir(p.parent);
  std::error_code ec;
  fs::remove_all(p.aside, ec);
  return true;
}

}  // namespace carril::sim
