#include "firmware/app/Controller.hpp"

#include <cmath>

namespace carril::fw {

namespace {
constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}

// Default pursuit distance: the floor seen 85% of the way down the image, near the bottom edge of
// the view. A longer look-ahead cuts 90 deg corners (measured on scenarios/square.yaml: cross-track
// rms 0.100 m at the image centre, 0.067 m here).
double default_lookahead(const CameraModel& cam) {
  Vec2 floor;
  if (cam.pixel_to_floor(Vec2(cam.cx(), 0.85 * (cam.mount().height - 1)), floor))
    return floor.norm();
  return 1.0;
}
}  // namespace

Controller::Controller(const FirmwareConfig& cfg, const hal::Clock& clock)
    : cfg_(cfg),
      clock_(clock),
      period_s_(1.0 / cfg.rate_hz),
      kin_(cfg.drive),
      cam_(cfg.camera),
      scanner_(cam_, cfg.mission),
      odom_(kin_),
      follower_(cfg.follower,
                cfg.follower.lookahead_m > 0 ? cfg.follower.lookahead_m : default_lookahead(cam_),
                cfg.mission.speed_mps),
      limiter_(cfg.limits, kin_, 1.0 / cfg.rate_hz),
      tick_budget_ns_(static_cast<std::int64_t>(0.5e9 / cfg.rate_hz)) {
  // Rate groups. Perception runs at about the camera's frame rate, obstacles at the lidar's.
  const auto per_frame =
      static_cast<std::uint32_t>(cfg.rate_hz / 30.0 > 1.0 ? cfg.rate_hz / 30.0 : 1.0);
  const auto per_scan =
      static_cast<std::uint32_t>(cfg.rate_hz / 20.0 > 1.0 ? cfg.rate_hz / 20.0 : 1.0);
  bool ok = true;
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_health>("health", 1, 0, us(20), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_odometry>("odometry", 1, 0, us(20), this));
  ok &= tasks_.add(
      TaskSpec::bind<&Controller::task_perception>("perception", per_frame, 0, us(300), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_obstacles>("obstacles", per_scan, 1 % per_scan,
                                                               us(50), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_behavior>("behavior", 1, 0, us(50), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_telemetry>("telemetry", 10, 9, us(50), this));
  assert(ok && "task table misconfigured");
  (void)ok;
  cmd_.wheel_count = static_cast<std::uint8_t>(kin_.wheel_count());
}

ActuatorCommand Controller::tick(const SensorFrame& frame) {
  const hal::TimeNs t0 = clock_.cpu_now_ns();
  frame_ = &frame;
  if (tick_ == 0) state_since_s_ = now_s();
  tasks_.run(tick_, clock_);
  ++tick_;
  const hal::TimeNs dt = clock_.cpu_now_ns() - t0;
  tick_stats_.add(dt);
  if (dt > tick_budget_ns_) ++telemetry_.tick_overruns;
  frame_ = nullptr;
  return cmd_;
}

void Controller::set_state(MissionState s) {
  if (s == state_) return;
  Event e;
  e.t_ns = frame_->now_ns;
  e.kind = EventKind::StateChange;
  e.from = state_;
  e.to = s;
  events_.push(e);
  state_ = s;
  state_since_s_ = now_s();
}

void Controller::raise(Fault f, std::uint16_t code) {
  if (fault_ != Fault::None) return;  // the first fault is the one reported
  fault_ = f;
  ++fault_counts_[std::size_t(f)];
  Event e;
  e.t_ns = frame_->now_ns;
  e.kind = EventKind::Fault;
  e.from = state_;
  e.to = MissionState::Fault;
  e.fault = f;
  e.code = code;
  events_.push(e);
  set_state(MissionState::Fault);
}

void Controller::task_health() {
  const SensorFrame& f = *frame_;
  for (int i = 0; i < f.wheels.count; ++i) {
    if (f.wheels.wheel[i].state == hal::DriveState::Fault) {
      raise(Fault::DriveFault, static_cast<std::uint16_t>(f.wheels.wheel[i].fault));
    }
  }
  if (f.camera != nullptr && f.camera->seq != last_frame_seq_) last_frame_s_ = now_s();
  if (f.scan != nullptr && f.scan->seq != last_scan_seq_) last_scan_s_ = now_s();
  // Before the first sample the init timeout applies (in INIT); afterwards the sensor's own.
  if (state_ != MissionState::Init) {
    if (now_s() - last_frame_s_ > cfg_.camera_timeout_s) raise(Fault::CameraTimeout);
    if (cfg_.lidar.present && now_s() - last_scan_s_ > cfg_.lidar.timeout_s)
      raise(Fault::ScannerTimeout);
  }
}

void Controller::task_odometry() {
  odom_.update(frame_->wheels);
}

void Controller::task_perception() {
  const hal::CameraFrame* cam = frame_->camera;
  fresh_obs_ = false;
  if (cam == nullptr || cam->seq == last_frame_seq_) return;
  last_frame_seq_ = cam->seq;
  if (!scanner_.scan(*cam, obs_)) {
    raise(Fault::CameraBadFrame);
    return;
  }
  fresh_obs_ = true;
  ++frames_processed_;
}

void Controller::task_obstacles() {
  const hal::LaserScan* scan = frame_->scan;
  if (scan == nullptr || scan->seq == last_scan_seq_) return;
  last_scan_seq_ = scan->seq;
  const double front = 0.5 * cfg_.footprint_length_m;
  const double half_w = 0.5 * cfg_.footprint_width_m + 0.05;
  const double c = std::cos(cfg_.lidar.yaw_rad), s = std::sin(cfg_.lidar.yaw_rad);
  bool ahead = false;
  for (int i = 0; i < scan->count; ++i) {
    const float r = scan->ranges_m[std::size_t(i)];
    // NaN/inf/zero are "no return": skip them before any comparison.
    if (!std::isfinite(r) || r < scan->range_min_m || r > scan->range_max_m || r <= 0.0F) {
      ++invalid_beams_;
      continue;
    }
    const double a = double(scan->angle_min_rad) + i * double(scan->angle_increment_rad);
    const double sx = double(r) * std::cos(a), sy = double(r) * std::sin(a);
    const double x = cfg_.lidar.x_m + c * sx - s * sy;
    const double y = cfg_.lidar.y_m + s * sx + c * sy;
    if (x > front && x < front + cfg_.protective_stop_m && std::fabs(y) < half_w) ahead = true;
  }
  obstacle_ahead_ = ahead;
  if (!ahead && clear_since_s_ <= 0.0) clear_since_s_ = now_s();
  if (ahead) clear_since_s_ = 0.0;
}

void Controller::task_behavior() {
  const SensorFrame& f = *frame_;
  Twist want;
  bool drives_up = f.wheels.count >= kin_.wheel_count();
  for (int i = 0; i < kin_.wheel_count() && drives_up; ++i) {
    drives_up = f.wheels.wheel[i].state == hal::DriveState::Enabled;
  }
  if (fresh_obs_) {
    frames_without_line_ = obs_.line_seen ? 0 : frames_without_line_ + 1;
    if (obs_.line_seen)
      last_line_side_ = obs_.line_points[obs_.line_points.size() - 1].y() >= 0 ? 1.0 : -1.0;
  }
  const bool line_gone = frames_without_line_ >= 3;
  const bool fresh = fresh_obs_;
  fresh_obs_ = false;  // each frame's observation is counted once

  switch (state_) {
    case MissionState::Init: {
      const bool sensors_up = last_frame_seq_ != 0 && (!cfg_.lidar.present || last_scan_seq_ != 0);
      if (drives_up && sensors_up) {
        set_state(obs_.line_seen ? MissionState::Follow : MissionState::Lost);
        search_start_yaw_ = odom_.pose().yaw;
        search_turned_ = 0.0;
      } else if (in_state_s() > cfg_.follower.init_timeout_s) {
        raise(drives_up ? (last_frame_seq_ == 0 ? Fault::CameraTimeout : Fault::ScannerTimeout)
                        : Fault::DriveEnableTimeout);
      }
      break;
    }
    case MissionState::Follow:
      if (obstacle_ahead_) {
        ++protective_stops_;
        set_state(MissionState::Blocked);
      } else if (obs_.end_seen) {
        // End mark in view: go and stop on it (its estimate is refined while it stays in view).
        end_mark_odom_ = to_world(odom_.pose(), obs_.end_point);
        set_state(MissionState::End);
      } else if (line_gone) {
        ++line_lost_;
        search_start_yaw_ = odom_.pose().yaw;
        search_turned_ = 0.0;
        set_state(MissionState::Lost);
      } else if (obs_.line_seen) {
        want = follower_.follow(obs_);
      }
      break;
    case MissionState::Lost:
      search_turned_ += std::fabs(wrap_angle(odom_.pose().yaw - search_start_yaw_));
      search_start_yaw_ = odom_.pose().yaw;
      if (fresh && obs_.line_seen) {
        ++line_reacquired_;
        set_state(MissionState::Follow);
      } else if (search_turned_ > cfg_.follower.search_max_turn_rad) {
        raise(Fault::LineNotFound);
      } else {
        want.wz = last_line_side_ * cfg_.follower.search_yaw_rate_radps;
      }
      break;
    case MissionState::End: {
      if (fresh && obs_.end_seen) end_mark_odom_ = to_world(odom_.pose(), obs_.end_point);
      const Vec2 target = to_robot(odom_.pose(), end_mark_odom_);
      if (end_done_ || target.norm() < cfg_.follower.end_tolerance_m || target.x() < 0.0) {
        end_done_ = true;
      } else {
        want = follower_.approach(target, kin_.holonomic());
      }
      break;
    }
    case MissionState::Blocked:
      if (!obstacle_ahead_ && clear_since_s_ > 0.0 && now_s() - clear_since_s_ > 1.0) {
        set_state(obs_.line_seen ? MissionState::Follow : MissionState::Lost);
      }
      break;
    case MissionState::Fault:
    case MissionState::Count:
      break;
  }

  // Commands: a fault quick-stops the drives; otherwise they run (or wait to come up).
  if (state_ == MissionState::Fault) {
    cmd_.drive = DriveRequest::QuickStop;
    cmd_.wheel_radps.fill(0.0F);
    cmd_.twist = {};
    limiter_.reset();
    return;
  }
  cmd_.drive = DriveRequest::Run;
  if (!drives_up) {
    want = {};
    limiter_.reset();
  }
  cmd_.twist = limiter_.apply(want, cmd_.wheel_radps.data());
}

void Controller::task_telemetry() {
  refresh_telemetry();
}

void Controller::refresh_telemetry() {
  Telemetry& t = telemetry_;
  t.ticks = tick_;
  t.tick_budget_us = double(tick_budget_ns_) / 1e3;
  t.tick_p50_us = tick_stats_.percentile_us(0.50);
  t.tick_p99_us = tick_stats_.percentile_us(0.99);
  t.tick_max_us = tick_stats_.max_us();
  t.tasks.clear();
  for (std::size_t i = 0; i < tasks_.size(); ++i) t.tasks.push_back(tasks_.counters(i));
  t.state = state_;
  t.fault = fault_;
  t.fault_counts = fault_counts_;
  t.line_lost_events = line_lost_;
  t.line_reacquired_events = line_reacquired_;
  t.protective_stops = protective_stops_;
  t.invalid_beams = invalid_beams_;
  t.frames_processed = frames_processed_;
  t.odom = odom_.pose();
  t.end_done = end_done_;
}

}  // namespace carril::fw
