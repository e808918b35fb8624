#include "host_sim/app/SimRun.hpp"

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "firmware/app/EventFormat.hpp"
#include "host_sim/alloc/AllocCounter.hpp"
#include "host_sim/app/CostmapOutputs.hpp"

namespace carril::sim {

namespace {
hal::TimeNs period_ns(double hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / hz));
}

std::string format_event(const fw::Event& e) {
  char buf[160];
  fw::format_event(e, double(e.t_ns) * 1e-9, buf, sizeof buf);
  return buf;
}
}  // namespace

SimRun::SimRun(const Scenario& scenario, std::uint64_t seed, const ConfigTweak& tweak)
    : scenario_(scenario),
      topo_(scenario, seed, tweak),
      metrics_(scenario),
      period_s_(1.0 / scenario.robot.control_rate_hz),
      period_ns_(period_ns(scenario.robot.control_rate_hz)),
      cam_period_ns_(period_ns(scenario.robot.camera.rate_hz)),
      scan_period_ns_(period_ns(scenario.robot.lidar.rate_hz)),
      alloc_base_(alloc::count_in_windows()) {
  rows_.reserve(std::size_t(scenario.duration_s * scenario.robot.control_rate_hz) + 16);
  if (topo_.config.mission == fw::MissionKind::Coverage && !topo_.static_map.empty()) {
    coverage_ = std::make_unique<CoverageScore>(scenario, topo_.config, topo_.static_map);
  }
}

const char* SimRun::state_name() const {
  return topo_.firmware->controller.state_name();
}

std::uint64_t SimRun::allocations_in_ticks() const {
  return alloc::count_in_windows() - alloc_base_;
}

void SimRun::publish_sensors(hal::TimeNs t) {
  SimWorld& w = topo_.world;
  if (t >= next_cam_ns_) {
    topo_.camera_renderer.render(w.pose(), topo_.camera.back_buffer(),
                                 topo_.camera.back_buffer_as_rendered());
    topo_.camera.publish(t);
    next_cam_ns_ += cam_period_ns_;
  }
  if (t >= next_scan_ns_) {
    topo_.lidar.scan(w, topo_.scanner.back_buffer());
    topo_.scanner.publish(t);
    next_scan_ns_ += scan_period_ns_;
  }
  if (topo_.lidar3d && t >= next_cloud_ns_) {
    // The sensor's convention is REP 103's (pitch positive nose down); the IMU's is nose up.
    const Attitude a = w.attitude();
    BodyPose3 body;
    body.x_m = w.pose().x;
    body.y_m = w.pose().y;
    body.z_m = a.z_m;
    body.roll_rad = a.roll_rad;
    body.pitch_rad = -a.pitch_rad;
    body.yaw_rad = w.pose().yaw_rad;
    topo_.lidar3d->render(w.height_field(), body, t, topo_.cloud.back_buffer());
    topo_.cloud.publish();
    next_cloud_ns_ += topo_.lidar3d->period_ns();
  }
  double vx = 0, vy = 0, wz = 0;
  w.body_velocity(vx, vy, wz);
  hal::ImuSample imu;
  imu.stamp_ns = t;
  imu.valid = true;
  imu.yaw_rate_radps = topo_.gyro.read(wz);
  // From the ground under the wheels (pitch positive nose up, roll positive left side up).
  const Attitude att = w.attitude();
  imu.roll_rad = float(att.roll_rad);
  imu.pitch_rad = float(att.pitch_rad);
  topo_.imu.publish(imu);
  for (int i = 0; i < w.wheel_count(); ++i) {
    float radps = 0.0F;
    double pos = 0.0;
    topo_.encoders.read(i, t, w.wheel_speed(i), w.wheel_position(i), radps, pos);
    topo_.drives.set_feedback(i, t, radps, pos);
  }
}

bool SimRun::step() {
  if (finished()) return false;
  const hal::TimeNs t = hal::TimeNs(tick_) * period_ns_;
  topo_.clock.set_now_ns(t);
  const std::vector<KidnapSpec>& kidnaps = scenario_.localisation.kidnaps;
  if (next_kidnap_ < kidnaps.size() && sim_time_s() >= kidnaps[next_kidnap_].t_s - 1e-9) {
    topo_.world.teleport(kidnaps[next_kidnap_].to);
    localisation_.kidnap(sim_time_s());
    ++next_kidnap_;
  }
  publish_sensors(t);

  // The firmware's tick: nothing in here may touch the heap.
  Eigen::internal::set_is_malloc_allowed(false);
  alloc::begin_window();
  topo_.app.step();
  alloc::end_window();
  Eigen::internal::set_is_malloc_allowed(true);

  // The firmware's step ended with the bus sync; the motors take what it latched, and the
  // physics runs one period in two sub-steps.
  float target[hal::kMaxWheels] = {};
  topo_.drives.take_setpoints(target);
  topo_.world.set_wheel_targets(target);
  topo_.world.step(period_s_ / 2);
  topo_.world.step(period_s_ / 2);
  // The slow rate group, in lockstep: after the tick whose telemetry it reports.
  if (tick_ % topo_.slow_divisor == topo_.slow_divisor - 1) topo_.slow.cycle(t, topo_.clock);
  ++tick_;

  // Score the state reached at the end of this period.
  const fw::Firmware& fw = *topo_.firmware;
  const fw::MissionState ms = fw.runner.state();
  const bool faulted = fw.controller.latched();
  TickSample s;
  s.t_s = sim_time_s();
  s.pose = topo_.world.pose();
  topo_.world.body_velocity(s.vx_mps, s.vy_mps, s.wz_radps);
  s.following = !faulted && ms.on_path;
  s.in_end_state = !faulted && (ms.status == fw::MissionStatus::Finishing ||
                                ms.status == fw::MissionStatus::Done);
  const double ct = metrics_.add(s);
  if (coverage_) coverage_->add(s.pose);
  if (fw.config().localisation.enabled) {
    const fw::Pose2 est = fw.bus.pose.get().pose;
    localisation_.add(s.t_s, std::hypot(est.x - s.pose.x, est.y - s.pose.y),
                      fw::wrap_angle(est.yaw - s.pose.yaw_rad));
  }
  rows_.push_back({s.t_s, s.pose.x, s.pose.y, s.pose.yaw_rad, s.vx_mps, s.vy_mps, s.wz_radps,
                   fw.controller.state_name(), ct});
  for (const ContactStart& c : topo_.world.take_new_contacts()) {
    metrics_.add_collision();
    collisions_.push_back({s.t_s, c.x, c.y});
  }
  while (metrics_.falls() < topo_.world.falls()) metrics_.add_fall();
  drain_events();

  if (metrics_.end_reached()) {
    result_ = "end_reached";
  } else if (!faulted && ms.status == fw::MissionStatus::Done && scenario_.mission.type == "goto") {
    result_ = "goal_reached";
  } else if (!faulted && ms.status == fw::MissionStatus::Done &&
             scenario_.mission.type == "coverage") {
    // Stopped by its own max_time_s is not done: the label says so.
    const bool timed_out = ms.phase != nullptr && std::strcmp(ms.phase, "time_limit") == 0;
    result_ = timed_out ? "coverage_time_limit" : "coverage_done";
  } else if (!faulted && ms.status == fw::MissionStatus::Done &&
             scenario_.mission.type == "waypoints") {
    result_ = "course_done";  // every lap driven to its last target
  } else if (faulted) {
    // Keep simulating for a second so the quick stop shows in the trajectory.
    if (fault_at_s_ < 0) fault_at_s_ = s.t_s;
    if (s.t_s - fault_at_s_ >= 1.0) result_ = "fault";
  } else if (s.t_s >= scenario_.duration_s - 1e-9) {
    result_ = "time_limit";
  }
  return !finished();
}

void SimRun::abort() {
  if (!finished()) result_ = "aborted";
}

void SimRun::drain_events() {
  fw::Event e;
  while (topo_.firmware->controller.events().pop(e)) {
    // Compute-time overruns measure this host, shared and noisy, not the robot: counted and
    // kept apart, not mixed into the mission's log.
    if (e.kind == fw::EventKind::Overrun) {
      overrun_log_.push_back(format_event(e));
    } else {
      log_.push_back(format_event(e));
    }
  }
}

std::vector<std::string> SimRun::take_log() {
  std::vector<std::string> out;
  out.swap(log_);
  return out;
}

namespace {
// expect's localisation keys against summary.json's figures; a null figure (never converged,
// never relocalised) fails.
void check_localisation(const ExpectSpec& x, RunSummary& r) {
  char buf[160];
  auto check = [&](const char* key, const std::optional<double>& bound,
                   const std::optional<double>& got, const char* never) {
    if (!bound) return;
    if (!got) {
      std::snprintf(buf, sizeof buf, "%s: expected <= %.3f, got %s", key, *bound, never);
    } else if (!(*got <= *bound)) {
      std::snprintf(buf, sizeof buf, "%s: expected <= %.3f, got %.3f", key, *bound, *got);
    } else {
      return;
    }
    r.unmet_expectations.emplace_back(buf);
  };
  check("max_time_to_converge_s", x.max_time_to_converge_s, r.time_to_converge_s,
        "never converged");
  check("max_localisation_rmse_m", x.max_localisation_rmse_m, r.localisation_rmse_m,
        "never converged");
  if (x.max_relocalise_s && r.relocalised_after_kidnaps_s.empty()) {
    check("max_relocalise_s", x.max_relocalise_s, std::nullopt, "no kidnap happened");
  }
  for (const std::optional<double>& k : r.relocalised_after_kidnaps_s) {
    check("max_relocalise_s", x.max_relocalise_s, k, "never relocalised");
  }
}
}  // namespace

RunSummary SimRun::summary(double wall_time_s) {
  fw::Firmware& firmware = *topo_.firmware;
  firmware.refresh_telemetry();
  const fw::FirmwareTelemetry& all = firmware.telemetry();
  const fw::ControllerTelemetry& tel = all.controller;
  RunSummary r;
  r.scenario = scenario_.name;
  r.result = finished() ? result_ : "aborted";
  r.sim_time_s = sim_time_s();
  r.wall_time_s = wall_time_s;
  r.real_time_factor = wall_time_s > 0 ? r.sim_time_s / wall_time_s : 0.0;
  r.ticks = long(tick_);
  r.tick_period_s = period_s_;
  r.tick_overruns = long(tel.tick_overruns);
  r.task_overrun_events = long(overrun_log_.size());
  r.tick_compute_p50_us = tel.tick_p50_us;
  r.tick_compute_p99_us = tel.tick_p99_us;
  r.tick_compute_max_us = tel.tick_max_us;
  r.heap_allocations_after_init = long(allocations_in_ticks());
  r.collisions = metrics_.collisions();
  r.mover_contacts = topo_.world.mover_contacts();
  r.falls = metrics_.falls();
  r.progress = metrics_.progress();
  r.laps = metrics_.laps();
  r.cross_track_rms_m = metrics_.cross_track_rms_m();
  r.cross_track_max_m = metrics_.cross_track_max_m();
  if (!localisation_.empty()) {
    const LocalisationScore ls = localisation_.score();
    r.time_to_converge_s = ls.time_to_converge_s;
    if (ls.converged_ticks > 0) {
      r.localisation_rmse_m = ls.rmse_m;
      r.localisation_max_error_m = ls.max_error_m;
      r.yaw_rmse_deg = ls.yaw_rmse_deg;
    }
    r.relocalised_after_kidnaps_s = ls.relocalised_after_s;
    if (!ls.relocalised_after_s.empty()) r.relocalised_after_kidnap_s = ls.relocalised_after_s[0];
    const fw::LocalisationTelemetry& lt = all.localisation;
    r.localisation_counters = {{"lost", long(lt.lost)},
                               {"lost_by_fit", long(lt.lost_by_fit)},
                               {"relocalisations", long(lt.relocalisations)},
                               {"spreads", long(lt.spreads)},
                               {"wrong_convergences", long(lt.wrong_convergences)},
                               {"alias_searches", long(lt.alias_searches)},
                               {"alias_ambiguous", long(lt.alias_ambiguous)},
                               {"alias_hypotheses", long(lt.alias_hypotheses)},
                               {"lost_turn_ticks", long(all.runner.lost_turn_ticks)},
                               {"lost_drive_ticks", long(all.runner.lost_drive_ticks)},
                               {"lost_legs", long(all.runner.lost_legs)},
                               {"lost_backs", long(all.runner.lost_backs)}};
  }
  const fw::MissionRunnerTelemetry& rt = all.runner;
  r.safety_counters = {{"obstacle_stops", long(rt.obstacle_stops)},
                       {"field_stops", long(rt.field_stops)},
                       {"field_slowdowns", long(rt.field_slowdowns)},
                       {"blind_ticks", long(rt.blind_ticks)},
                       {"check_stops", long(rt.check_stops)},
                       {"check_slowdowns", long(rt.check_slowdowns)},
                       {"check_alternatives", long(rt.check_alternatives)},
                       {"moving_returns", long(all.obstacles.moving_returns)}};
  r.blocked_max_s = rt.blocked_max_s;
  r.mission = all.mission;
  for (const fw::MissionCounter& c : all.mission_counters) {
    r.mission_counters.emplace_back(c.name, long(c.value));
  }
  // summary.json's contract keys for the line counts: follow_line's counters of those names.
  r.line_lost_events = int(firmware.mission_counter("line_lost_events"));
  r.line_reacquired_events = int(firmware.mission_counter("line_reacquired_events"));
  r.obstacles_avoided = int(firmware.mission_counter("obstacles_avoided"));
  r.end_reached = metrics_.end_reached();
  r.end_stop_error_m = metrics_.end_stop_error_m();
  r.path_length_m = metrics_.path_length_m();
  r.mean_speed_mps = metrics_.mean_speed_mps();
  r.max_abs_wz_radps = metrics_.max_abs_wz_radps();
  r.final_state = tel.state;
  r.mission_status = fw::mission_status_name(tel.status);
  if (tel.fault != fw::Fault::None) r.fault = fw::fault_name(tel.fault);

  // Expectations. A run that faulted or was aborted never passes.
  auto miss = [&](const char* fmt, double want, double got) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, want, got);
    r.unmet_expectations.emplace_back(buf);
  };
  const ExpectSpec& x = scenario_.expect;
  // A run that ends in the fault its scenario expects (e.g. no_path) is not failed for it.
  if (r.result == "fault" && !(x.fault && *x.fault == r.fault)) {
    r.unmet_expectations.push_back("run ended in fault " + r.fault);
  }
  if (r.result == "aborted") r.unmet_expectations.emplace_back("run was aborted");
  if (x.end_reached && *x.end_reached != r.end_reached) {
    miss("end_reached: expected %.0f, got %.0f", *x.end_reached ? 1.0 : 0.0,
         r.end_reached ? 1.0 : 0.0);
  }
  if (x.max_collisions && r.collisions > *x.max_collisions) {
    miss("max_collisions: expected <= %.0f, got %.0f", *x.max_collisions, r.collisions);
  }
  if (x.max_cross_track_rms_m && !(r.cross_track_rms_m <= *x.max_cross_track_rms_m)) {
    miss("max_cross_track_rms_m: expected <= %.4f, got %.4f", *x.max_cross_track_rms_m,
         r.cross_track_rms_m);
  }
  if (x.min_progress && r.progress < *x.min_progress - 1e-9) {
    miss("min_progress: expected >= %.3f, got %.3f", *x.min_progress, r.progress);
  }
  if (x.max_end_stop_error_m) {
    if (!r.end_stop_error_m) {
      char buf[120];
      std::snprintf(buf, sizeof buf,
                    "max_end_stop_error_m: expected <= %.4f, got no stop on an end mark",
                    *x.max_end_stop_error_m);
      r.unmet_expectations.emplace_back(buf);
    } else if (!(*r.end_stop_error_m <= *x.max_end_stop_error_m)) {
      miss("max_end_stop_error_m: expected <= %.4f, got %.4f", *x.max_end_stop_error_m,
           *r.end_stop_error_m);
    }
  }
  for (const fw::TaskCounters& t : tel.tasks) {
    r.tasks.push_back({t.name, long(t.runs), long(t.overruns), t.p50_us, t.p99_us, t.max_us});
  }
  score_goto(scenario_, firmware, topo_.world.pose(), r);
  // The waypoint course's goal: the whole course driven (expect goal_reached checks it).
  if (scenario_.mission.type == "waypoints") {
    r.goal_reached = firmware.waypoints.current() == fw::WaypointMission::State::Done;
  }
  check_cells(scenario_, firmware, r);
  if (x.goal_reached && (!r.goal_reached || *r.goal_reached != *x.goal_reached)) {
    miss("goal_reached: expected %.0f, got %.0f", *x.goal_reached ? 1.0 : 0.0,
         r.goal_reached.value_or(false) ? 1.0 : 0.0);
  }
  if (x.max_goal_error_m && !(r.goal_error_m && *r.goal_error_m <= *x.max_goal_error_m)) {
    miss("max_goal_error_m: expected <= %.3f, got %.3f", *x.max_goal_error_m,
         r.goal_error_m.value_or(-1.0));
  }
  if (x.max_goal_yaw_error_deg &&
      !(r.goal_yaw_error_deg && *r.goal_yaw_error_deg <= *x.max_goal_yaw_error_deg)) {
    miss("max_goal_yaw_error_deg: expected <= %.1f, got %.1f", *x.max_goal_yaw_error_deg,
         r.goal_yaw_error_deg.value_or(-1.0));
  }
  check_localisation(x, r);
  if (x.min_replans && r.replans < *x.min_replans) {
    miss("min_replans: expected >= %.0f, got %.0f", *x.min_replans, double(r.replans));
  }
  if (x.fault && r.fault != *x.fault) {
    r.unmet_expectations.push_back("fault: expected " + *x.fault + ", got " +
                                   (r.fault.empty() ? std::string("none") : r.fault));
  }
  if (coverage_) {
    const CoverageFigures f = coverage_->figures();
    r.coverage = f.covered;
    r.coverage_overlap = f.overlap;
    r.coverage_area_m2 = f.area_m2;
    r.coverage_lower_bound_s = f.lower_bound_s;
    r.coverage_time_ratio = r.sim_time_s / f.lower_bound_s;
  }
  if (x.min_coverage && !(r.coverage && *r.coverage >= *x.min_coverage)) {
    miss("min_coverage: expected >= %.3f, got %.3f", *x.min_coverage, r.coverage.value_or(-1.0));
  }
  if (x.max_coverage_time_ratio &&
      !(r.coverage_time_ratio && *r.coverage_time_ratio <= *x.max_coverage_time_ratio)) {
    miss("max_coverage_time_ratio: expected <= %.2f, got %.2f", *x.max_coverage_time_ratio,
         r.coverage_time_ratio.value_or(-1.0));
  }
  if (x.min_laps && r.laps < *x.min_laps)
    miss("min_laps: expected >= %.0f, got %.0f", *x.min_laps, r.laps);
  r.passed = r.unmet_expectations.empty();
  return r;
}

}  // namespace carril::sim
