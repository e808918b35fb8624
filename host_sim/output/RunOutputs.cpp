#include "host_sim/output/RunOutputs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "host_sim/output/Json.hpp"
#include "host_sim/output/Plots.hpp"

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
  // The temporary lives in the target's directory so that rename() is atomic (same filesystem);
  // the pid keeps concurrent runs writing the same file from trampling each other's temporary.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  auto fail = [&](const char* what, int err, bool remove_tmp) {
    if (remove_tmp) ::unlink(tmp.c_str());
    error = "cannot write " + path + ": " + what + ": " + errno_text(err);
    return false;
  };

  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return fail("open", errno, false);
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      return fail("write", err, true);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    return fail("fsync", err, true);
  }
  if (::close(fd) != 0) return fail("close", errno, true);
  if (::rename(tmp.c_str(), path.c_str()) != 0) return fail("rename", errno, true);
  fsync_dir(std::filesystem::path(path).parent_path());
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

bool write_run_outputs(const std::string& dir, const Scenario& scenario,
                       const std::vector<TrajectoryRow>& rows,
                       const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                       std::string& error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    error = "cannot create output directory " + dir + ": " + ec.message();
    return false;
  }
  const fs::path base(dir);
  auto write = [&](const char* name, const std::string& content) {
    return write_file_atomic((base / name).string(), content, error);
  };

  if (!write("trajectory.csv", trajectory_to_csv(rows))) return false;

  std::string png;
  if (!render_trajectory_png(scenario, rows, collisions, summary, png, error)) return false;
  if (!write("trajectory.png", png)) return false;
  if (!render_velocities_png(rows, summary, png, error)) return false;
  if (!write("velocities.png", png)) return false;

  // Last, so that a summary on disk means the run's other outputs are complete too.
  return write("summary.json", summary_to_json(summary));
}

}  // namespace carril::sim
