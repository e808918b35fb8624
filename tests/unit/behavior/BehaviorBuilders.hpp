#pragma once
// Builders for the behaviour tests: a straight tape's TrackState, a synthetic lidar (ray-cast
// against line segments in the odometry frame, through a real hal::LaserScan and
// ObstacleField::update) and a small closed-loop simulator that integrates the commanded twist.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "firmware/behavior/BypassPlanner.hpp"
#include "firmware/behavior/LineBehavior.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/mission/MissionRunner.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "hal/Types.hpp"

namespace carril::fw::test {

constexpr double kDt = 0.01;  // [s]

using Phases = std::vector<std::string>;

inline void expect_still(const Twist& t) {
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_EQ(t.vy, 0.0);
  EXPECT_EQ(t.wz, 0.0);
}

struct Segment {
  Vec2 a, b;
};
using World = std::vector<Segment>;

// Axis-aligned box [x0, x1] x [y0, y1], odometry frame.
inline void add_box(World& w, double x0, double x1, double y0, double y1) {
  w.push_back({{x0, y0}, {x1, y0}});
  w.push_back({{x1, y0}, {x1, y1}});
  w.push_back({{x1, y1}, {x0, y1}});
  w.push_back({{x0, y1}, {x0, y0}});
}

// A box given in a frame at `o` with direction `h` (x along, y to the left).
inline void add_box_in(World& w, const Vec2& o, double h, double x0, double x1, double y0,
                       double y1) {
  const Pose2 f{o.x(), o.y(), h};
  const Vec2 c[4] = {to_world(f, {x0, y0}), to_world(f, {x1, y0}), to_world(f, {x1, y1}),
                     to_world(f, {x0, y1})};
  for (int i = 0; i < 4; ++i) w.push_back({c[i], c[(i + 1) % 4]});
}

inline void add_wall(World& w, const Vec2& a, const Vec2& b) {
  w.push_back({a, b});
}

inline double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// A 360 deg scan (1440 beams) from a sensor at the robot centre, taken at `pose`. Beams that hit
// nothing read +inf (skipped by ObstacleField, as a real "no return").
inline hal::LaserScan scan_of(const World& world, const Pose2& pose, int beams = 1440) {
  hal::LaserScan s;
  s.seq = 1;
  s.count = std::uint16_t(beams);
  s.angle_min_rad = float(-kPi);
  s.angle_increment_rad = float(2.0 * kPi / beams);
  s.range_min_m = 0.02F;
  s.range_max_m = 12.0F;
  const Vec2 p(pose.x, pose.y);
  for (int i = 0; i < beams; ++i) {
    const double a = pose.yaw + double(s.angle_min_rad) + i * double(s.angle_increment_rad);
    const Vec2 r(std::cos(a), std::sin(a));
    double best = 1e9;
    for (const Segment& seg : world) {
      const Vec2 e = seg.b - seg.a;
      const double den = cross(r, e);
      if (std::fabs(den) < 1e-12) continue;
      const double t = cross(seg.a - p, e) / den;
      const double u = cross(seg.a - p, r) / den;
      if (t > 1e-6 && u >= 0.0 && u <= 1.0 && t < best) best = t;
    }
    s.ranges_m[std::size_t(i)] = best < 12.0 ? float(best) : std::numeric_limits<float>::infinity();
  }
  return s;
}

inline ObstacleField field_of(const World& world, const Pose2& pose, const Footprint& fp = {}) {
  ObstacleField f(fp, 0.0, 0.0, 0.0);
  f.update(scan_of(world, pose), pose);
  return f;
}

// A straight tape through `p0` with direction `h` (odometry frame), ending `end_s` metres along
// from p0: the TrackState a correct TapeMap would report for a robot at `odom`.
struct StraightTape {
  Vec2 p0 = Vec2::Zero();
  double h = 0.0;
  double end_s = 1e3;

  Vec2 u() const { return {std::cos(h), std::sin(h)}; }
  double along(const Pose2& o) const { return (Vec2(o.x, o.y) - p0).dot(u()); }
  TrackState track(const Pose2& o, double lookahead_m) const {
    TrackState t;
    t.valid = true;
    const double s = along(o);
    const Vec2 nearest = p0 + s * u();
    t.lateral_m = to_robot(o, nearest).y();
    t.heading_err_rad = wrap_angle(h - o.yaw);
    t.tape_heading_odom = h;
    t.remaining_m = std::fmax(0.0, end_s - s);
    t.lookahead = to_robot(o, nearest + std::fmin(lookahead_m, t.remaining_m) * u());
    return t;
  }
};

inline Twist integrate_pose(Pose2& p, const Twist& t, double dt) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  p.x += (c * t.vx - s * t.vy) * dt;
  p.y += (s * t.vx + c * t.vy) * dt;
  p.yaw = wrap_angle(p.yaw + t.wz * dt);
  return t;
}

// Closed loop around one LineBehavior: the drives follow the command at once (the measured
// twist is last tick's command), the camera sees the straight tape, the lidar scans `world` every
// tick. `script` may change the input after the defaults are set.
struct Sim {
  BehaviorConfig cfg;
  ObstacleStopConfig stop;  // the mission runner's obstacle question, asked in FOLLOW
  StrategyConfig scfg;
  Footprint fp;
  bool holonomic;
  LineController line;
  BypassPlanner planner;
  LineBehavior mb;
  ObstacleField field;

  double t = 0.0;
  Pose2 pose;
  Twist last;  // last command
  bool drives = true, camera = true, scanner = true, imu = true;
  StraightTape tape;
  bool tape_in_view = true;  // the camera sees the tape (while it is ahead)
  bool tape_in_map = false;  // the TapeMap holds points (a frame with tape fills it)
  bool far_from_map = true;  // report the far tape segment (as the Controller does)
  int frame_every = 1;       // a fresh camera frame every this many ticks
  bool lidar = true;
  World world;
  bool end_known = false;
  Vec2 end_odom = Vec2::Zero();
  std::function<void(BehaviorInput&)> script;

  int ticks = 0;
  BehaviorInput last_in;            // the input of the last step
  BehaviorOutput out;               // and its output
  std::vector<std::string> phases;  // every take_phase_change(), in order
  std::vector<Fault> faults;

  explicit Sim(bool holo, Strategy s = Strategy::Marks, BehaviorConfig c = {})
      : cfg(c),
        scfg(strategy(s)),
        holonomic(holo),
        line(scfg, holo),
        planner(cfg.avoid, fp, holo),
        mb(cfg, line, planner, holo),
        field(fp, 0.0, 0.0, 0.0) {}

  static StrategyConfig strategy(Strategy s) {
    StrategyConfig sc;
    sc.strategy = s;
    return sc;
  }

  bool sees_tape() const {
    // The camera looks 0.7 m to 1.8 m ahead: no tape in view within 0.7 m of its end.
    return tape_in_view && tape.end_s - tape.along(pose) > 0.7;
  }

  BehaviorInput input() {
    BehaviorInput in;
    in.t_s = t;
    in.drives_ready = drives;
    in.camera_ready = camera;
    in.scanner_ready = scanner;
    in.imu_ready = imu;
    in.fresh_frame = camera && ticks % frame_every == 0;
    in.line_visible = in.fresh_frame && sees_tape();
    if (in.line_visible) {
      tape_in_map = true;  // the Controller adds the frame's points to the TapeMap
      const Vec2 p = tape.p0 + (tape.along(pose) + 0.7) * tape.u();
      in.line_near = to_robot(pose, p);
      in.line_near_angle = wrap_angle(tape.h - pose.yaw);
    }
    const double la =
        scfg.strategy == Strategy::Pid ? scfg.pid_lookahead_m : scfg.marks_lookahead_m;
    if (tape_in_map) {
      in.track = tape.track(pose, la);
      // TapeMap::far_segment: the far end of what the camera last saw, on the straight tape.
      in.tape_far_valid = far_from_map;
      in.tape_far_point = tape.p0 + std::fmin(tape.along(pose) + 1.8, tape.end_s) * tape.u();
      in.tape_far_heading = tape.h;
    }
    in.end_known = end_known;
    in.end_odom = end_odom;
    in.odom = pose;
    in.measured = last;
    if (lidar) {
      field.update(scan_of(world, pose), pose);
      in.fresh_scan = true;
      in.obstacles = &field;
      // As MissionRunner's ObstacleGuard answers it for FollowLineMission.
      in.obstacle_ahead = mb.state() == LineState::Follow && field.valid() &&
                          field.ahead_m(pose, stop.corridor_margin_m, 5.0) < stop.stop_m;
    }
    return in;
  }

  const BehaviorOutput& step() {
    BehaviorInput in = input();
    if (script) script(in);
    last_in = in;
    out = mb.step(in, kDt);
    if (out.clear_map) tape_in_map = false;
    if (out.fault != Fault::None) faults.push_back(out.fault);
    if (const char* p = mb.take_phase_change()) phases.emplace_back(p);
    last = integrate_pose(pose, out.twist, kDt);
    ++ticks;
    t = ticks * kDt;
    return out;
  }

  // Steps until `done` holds after a step (true) or `max_ticks` pass (false).
  bool run_until(const std::function<bool()>& done, int max_ticks) {
    for (int i = 0; i < max_ticks; ++i) {
      step();
      if (done()) return true;
    }
    return false;
  }
  bool run_until_state(LineState s, int max_ticks) {
    return run_until([&] { return mb.state() == s; }, max_ticks);
  }
  bool run_until_phase(const std::string& p, int max_ticks) {
    return run_until([&] { return p == mb.phase(); }, max_ticks);
  }

  // Ready from the first tick, on the tape and aligned: START wait -> find -> FOLLOW.
  void start_on_tape() {
    step();
    step();
  }
};

}  // namespace carril::fw::test
