#include "firmware/app/Controller.hpp"

#include <cmath>

namespace carril::fw {

namespace {
constexpr std::int64_t us(double v) {
  return static_cast<std::int64_t>(v * 1e3);
}

Footprint footprint_of(const FirmwareConfig& c) {
  return {0.5 * c.footprint_length_m, 0.5 * c.footprint_width_m};
}
}  // namespace

Controller::Controller(const FirmwareConfig& cfg, const hal::Clock& clock)
    : cfg_(cfg),
      clock_(clock),
      period_s_(1.0 / cfg.rate_hz),
      kin_(cfg.drive),
      cam_(cfg.camera),
      detector_(cam_, cfg.detector),
      odom_(kin_),
      obstacles_(footprint_of(cfg), cfg.lidar.x_m, cfg.lidar.y_m, cfg.lidar.yaw_rad),
      scan_health_(cfg.health.scan),
      frame_health_(cfg.health.frame),
      imu_health_(cfg.health.imu),
      line_(cfg.strategy, kin_.holonomic()),
      planner_(cfg.behavior.avoid, footprint_of(cfg)),
      behavior_(cfg.behavior, line_, planner_, kin_.holonomic()),
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
      TaskSpec::bind<&Controller::task_perception>("perception", per_frame, 0, us(400), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_obstacles>("obstacles", per_scan, 1 % per_scan,
                                                               us(60), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_behavior>("behavior", 1, 0, us(80), this));
  ok &= tasks_.add(TaskSpec::bind<&Controller::task_telemetry>("telemetry", 10, 9, us(50), this));
  assert(ok && "task table misconfigured");
  (void)ok;
  cmd_.wheel_count = static_cast<std::uint8_t>(kin_.wheel_count());
}

ActuatorCommand Controller::tick(const SensorFrame& frame) {
  const hal::TimeNs t0 = clock_.cpu_now_ns();
  frame_ = &frame;
  fresh_frame_ = fresh_scan_ = false;
  const MissionState before = state();
  tasks_.run(tick_, clock_);
  if (state() != before) log_state(before, state());
  ++tick_;
  const hal::TimeNs dt = clock_.cpu_now_ns() - t0;
  tick_stats_.add(dt);
  if (dt > tick_budget_ns_) ++telemetry_.tick_overruns;
  frame_ = nullptr;
  return cmd_;
}

void Controller::log_state(MissionState from, MissionState to) {
  Event e;
  e.t_ns = frame_->now_ns;
  e.kind = EventKind::StateChange;
  e.from = from;
  e.to = to;
  events_.push(e);
}

void Controller::raise(Fault f, std::uint16_t code, MissionState in_state) {
  if (fault_ != Fault::None) return;  // the first fault is the one reported
  fault_ = f;
  ++fault_counts_[std::size_t(f)];
  Event e;
  e.t_ns = frame_->now_ns;
  e.kind = EventKind::Fault;
  e.from = in_state;
  e.to = MissionState::Fault;
  e.fault = f;
  e.code = code;
  events_.push(e);
}

void Controller::task_health() {
  const SensorFrame& f = *frame_;
  for (int i = 0; i < f.wheels.count; ++i) {
    if (f.wheels.wheel[i].state == hal::DriveState::Fault) {
      raise(Fault::DriveFault, static_cast<std::uint16_t>(f.wheels.wheel[i].fault), state());
    }
  }
  // Timeouts count from the first sample; before it, START's init timeout applies.
  if (last_frame_seq_ != 0 && now_s() - last_frame_s_ > cfg_.camera_timeout_s)
    raise(Fault::CameraTimeout, 0, state());
  if (cfg_.lidar.present && last_scan_seq_ != 0 && now_s() - last_scan_s_ > cfg_.lidar.timeout_s) {
    raise(Fault::ScannerTimeout, 0, state());
  }
  if (cfg_.imu_present) {
    switch (imu_health_.add(f.imu, now_s(), odom_.twist().wz)) {
      case ImuVerdict::OutOfRange:
        raise(Fault::ImuOutOfRange, 0, state());
        break;
      case ImuVerdict::Frozen:
        raise(Fault::ImuFrozen, 0, state());
        break;
      case ImuVerdict::Ok:
        break;
    }
  }
}

void Controller::task_odometry() {
  odom_.update(frame_->wheels);
}

void Controller::task_perception() {
  const hal::CameraFrame* cam = frame_->camera;
  if (cam == nullptr || cam->seq == last_frame_seq_) return;
  last_frame_seq_ = cam->seq;
  last_frame_s_ = now_s();
  if (!detector_.detect(*cam, det_)) {
    raise(Fault::CameraBadFrame, 0, state());
    return;
  }
  switch (frame_health_.add(*cam, odom_.pose())) {
    case FrameVerdict::Blank:
      raise(Fault::CameraBlank, 0, state());
      return;
    case FrameVerdict::Frozen:
      raise(Fault::CameraFrozen, 0, state());
      return;
    case FrameVerdict::Ok:
      break;
  }
  fresh_frame_ = true;
  ++frames_processed_;
  const Pose2& pose = odom_.pose();
  if (det_.detected) map_.add(pose, det_.centerline_floor.begin(), det_.centerline_floor.size());
  // The end mark's position is only trusted when all of it is in view.
  if (det_.end_detected && !det_.end_blob.touches_edge) {
    // A disc seen in perspective has its image centroid pulled toward the near side; the middle
    // of its nearest and farthest points (bottom and top of the blob) on the floor is its centre.
    const Blob& b = det_.end_blob;
    const double uc = 0.5 * (b.u_min + b.u_max);
    Vec2 near, far;
    const bool ok = cam_.pixel_to_floor(Vec2(uc, b.v_max + 0.5), near) &&
                    cam_.pixel_to_floor(Vec2(uc, b.v_min - 0.5), far);
    end_odom_ = to_world(pose, ok ? Vec2(0.5 * (near + far)) : det_.end_floor);
    end_known_ = true;
  }
}

void Controller::task_obstacles() {
  const hal::LaserScan* scan = frame_->scan;
  if (scan == nullptr || scan->seq == last_scan_seq_) return;
  last_scan_seq_ = scan->seq;
  last_scan_s_ = now_s();
  if (!scan_health_.add(*scan)) raise(Fault::ScannerBlind, 0, state());
  obstacles_.update(*scan, odom_.pose());
  fresh_scan_ = true;
}

void Controller::task_behavior() {
  const SensorFrame& f = *frame_;
  bool drives_up = f.wheels.count >= kin_.wheel_count();
  for (int i = 0; i < kin_.wheel_count() && drives_up; ++i) {
    drives_up = f.wheels.wheel[i].state == hal::DriveState::Enabled;
  }
  if (fault_ == Fault::None) {
    BehaviorInput in;
    in.t_s = now_s();
    in.drives_ready = drives_up;
    in.camera_ready = last_frame_seq_ != 0;
    in.scanner_ready = !cfg_.lidar.present || last_scan_seq_ != 0;
    in.fresh_frame = fresh_frame_;
    in.line_visible = det_.detected;
    if (det_.detected && det_.centerline_floor.size() >= 2) {
      const Vec2 n0 = det_.centerline_floor[0], n1 = det_.centerline_floor[1];
      in.line_near = n0;
      in.line_near_angle = std::atan2(n1.y() - n0.y(), n1.x() - n0.x());
    }
    in.fresh_scan = fresh_scan_;
    in.track = map_.track(odom_.pose(),
                          cfg_.strategy.strategy == Strategy::Pid ? cfg_.strategy.pid_lookahead_m
                                                                  : cfg_.strategy.marks_lookahead_m,
                          cfg_.tape_preview_m);
    in.tape_far_valid = map_.far_segment(0.3, in.tape_far_point, in.tape_far_heading);
    in.end_known = end_known_;
    in.end_odom = end_odom_;
    in.odom = odom_.pose();
    in.measured = odom_.twist();
    in.obstacles = obstacles_.valid() ? &obstacles_ : nullptr;
    in.tape = &map_;
    const MissionState was = behavior_.state();
    const BehaviorOutput out = behavior_.step(in, period_s_);
    if (out.clear_map) map_.clear();
    if (out.fault != Fault::None) raise(out.fault, 0, was);
    Twist want = out.twist;
    if (!drives_up) {
      want = {};
      limiter_.reset();
    }
    cmd_.drive = DriveRequest::Run;
    cmd_.twist = limiter_.apply(want, cmd_.wheel_radps.data());
  }
  if (const char* phase = behavior_.take_phase_change()) {
    Event e;
    e.t_ns = f.now_ns;
    e.kind = EventKind::Phase;
    e.from = e.to = behavior_.state();
    e.phase = phase;
    events_.push(e);
  }
  // A latched fault quick-stops the drives, whatever the behaviour wanted.
  if (fault_ != Fault::None) {
    cmd_.drive = DriveRequest::QuickStop;
    cmd_.wheel_radps.fill(0.0F);
    cmd_.twist = {};
    limiter_.reset();
  }
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
  t.state = fault_ != Fault::None ? MissionState::Fault : behavior_.state();
  t.phase = behavior_.phase();
  t.fault = fault_;
  t.fault_counts = fault_counts_;
  t.line_lost_events = behavior_.line_lost_events();
  t.line_reacquired_events = behavior_.line_reacquired_events();
  t.reversed_sightings = behavior_.reversed_sightings();
  t.obstacles_avoided = behavior_.obstacles_avoided();
  t.invalid_beams = obstacles_.invalid_beams();
  t.scan_valid_fraction = scan_health_.valid_fraction();
  t.frame_spread = frame_health_.last_spread();
  t.frames_processed = frames_processed_;
  t.odom = odom_.pose();
  t.end_done = behavior_.end_done();
}

}  // namespace carril::fw
