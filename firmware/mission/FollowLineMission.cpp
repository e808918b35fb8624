#include "firmware/mission/FollowLineMission.hpp"

#include "firmware/core/Param.hpp"

#include <cmath>
#include <cstring>

namespace carril::fw {

std::span<const Param<FollowLineConfig>> FollowLineConfig::params() {
  using C = FollowLineConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, tape_preview_m, "m", 0.0, 5.0,
                   "how far along the remembered tape corners are looked for"),
  };
  return kParams;
}

Status FollowLineConfig::validate() const {
  return Checks("follow_line")
      .params(*this, params())
      .nested(strategy.validate())
      .nested(behavior.validate())
      .result();
}

FollowLineMission::FollowLineMission(const FollowLineConfig& cfg, const Footprint& footprint,
                                     bool holonomic, bool lidar_present,
                                     const Topic<OdometryMsg>& odom,
                                     const Topic<LineObservation>& line,
                                     const Topic<ObstacleField>& obstacles)
    : cfg_(cfg),
      lidar_present_(lidar_present),
      line_(cfg.strategy, holonomic),
      planner_(cfg.behavior.avoid, footprint, holonomic),
      behavior_(cfg.behavior, line_, planner_, holonomic),
      odom_(odom),
      obs_(line),
      obstacles_(obstacles) {}

void FollowLineMission::enter(const MissionContext& ctx) {
  behavior_.begin(ctx.t_s, odom_.get().pose.yaw);
}

bool FollowLineMission::remember(const LineObservation& obs) {
  const LineDetection& det = obs.detection;
  bool seen = det.sure;
  if (det.sure) {
    map_.add(obs.pose, det.centerline_floor.begin(), det.centerline_floor.size());
  } else if (det.detected) {
    // A piece too small to be tape on its own (worn tape between gaps, or a speck): tape only
    // where it continues what was remembered (or, just after a bypass, what was remembered before
    // it). Added when it reaches past memory's end or memory is empty: a piece replaces memory
    // from its near point on, and memory already holds the tape it lies on.
    bool extends = false;
    const TapeMap& context = map_.empty() ? before_bypass_ : map_;
    seen = context.continues(obs.pose, det.centerline_floor.begin(), det.centerline_floor.size(),
                             extends);
    ++(seen ? pieces_taken_ : pieces_refused_);
    if (seen && (extends || map_.empty())) {
      map_.add(obs.pose, det.centerline_floor.begin(), det.centerline_floor.size());
    }
  }
  if (obs.end_visible) {
    end_odom_ = to_world(obs.pose, obs.end_floor);
    end_known_ = true;
  }
  if (obs.end_glimpsed) {
    end_glimpse_odom_ = to_world(obs.pose, det.end_floor);
    end_glimpsed_ = true;
  }
  return seen;
}

BehaviorInput FollowLineMission::inputs(const MissionContext& ctx) {
  BehaviorInput in;
  in.fresh_frame = obs_.fresh();
  if (in.fresh_frame) line_seen_ = remember(obs_.take());
  in.fresh_scan = obstacles_.fresh();
  if (in.fresh_scan) obstacles_.take();
  const OdometryMsg& odom = odom_.get();
  const LineDetection& det = obs_.peek().detection;
  in.t_s = ctx.t_s;
  in.drives_ready = ctx.drives_ready;
  in.imu_ready = ctx.imu_ready;
  in.camera_ready = obs_.ever();
  in.scanner_ready = !lidar_present_ || obstacles_.ever();
  in.line_visible = line_seen_;
  if (line_seen_ && det.centerline_floor.size() >= 2) {
    const Vec2 n0 = det.centerline_floor[0], n1 = det.centerline_floor[1];
    in.line_near = n0;
    in.line_near_angle = std::atan2(n1.y() - n0.y(), n1.x() - n0.x());
  }
  const StrategyConfig& s = cfg_.strategy;
  in.track =
      map_.track(odom.pose, s.strategy == Strategy::Pid ? s.pid_lookahead_m : s.marks_lookahead_m,
                 cfg_.tape_preview_m);
  in.end_known = end_known_;
  in.end_odom = end_odom_;
  in.end_glimpsed = end_glimpsed_;
  in.end_glimpse_odom = end_glimpse_odom_;
  in.odom = odom.pose;
  in.measured = odom.twist;
  in.obstacles = obstacles_.peek().valid() ? &obstacles_.peek() : nullptr;
  in.tape = &map_;
  if (const CostmapView* c = costmap(); c != nullptr && c->updates() > 0) {
    in.costmap = &c->master();
    in.costmap_updated = c->updates() != costmap_seen_;
    costmap_seen_ = c->updates();
  }
  // The runner answers the obstacle question; FOLLOW is the state that acts on it, and the far
  // tape segment (where the tape runs into the obstacle) is only read then.
  in.obstacle_ahead = behavior_.state() == LineState::Follow && ctx.obstacle_ahead();
  in.tape_far_valid =
      in.obstacle_ahead && map_.far_segment(0.3, in.tape_far_point, in.tape_far_heading);
  return in;
}

MissionOutput FollowLineMission::update(const MissionContext& ctx) {
  const BehaviorInput in = inputs(ctx);
  const BehaviorOutput out = behavior_.step(in, ctx.dt_s);
  if (out.clear_map) {
    if (out.rejoined) {
      before_bypass_ = map_;
    } else {
      before_bypass_.clear();
    }
    map_.clear();
  }
  MissionOutput o;
  o.motion.twist = out.twist;
  o.motion.guarded = behavior_.state() == LineState::Follow;
  o.fault = out.fault;
  return o;
}

MissionState FollowLineMission::state() const {
  MissionState s;
  const LineState st = behavior_.state();
  s.id = static_cast<std::uint8_t>(st);
  s.name = state_name(st);
  s.phase = behavior_.phase();
  s.on_path = st == LineState::Follow;
  switch (st) {
    case LineState::Start:
      s.status = MissionStatus::Starting;
      // Waiting for the drives and sensors: behavior.init_timeout_s is its own limit.
      s.waiting = std::strcmp(s.phase, "wait") == 0;
      break;
    case LineState::Follow:
    case LineState::Search:
    case LineState::Avoid:
      s.status = MissionStatus::Active;
      break;
    case LineState::End:
      s.status = behavior_.end_done()        ? MissionStatus::Done
                 : behavior_.end_revealing() ? MissionStatus::Active
                                             : MissionStatus::Finishing;
      break;
    case LineState::Fault:
    case LineState::Count:
      s.status = MissionStatus::Failed;
      break;
  }
  return s;
}

void FollowLineMission::counters(MissionCounters& out) const {
  out.clear();
  out.push_back({"line_lost_events", behavior_.line_lost_events()});
  out.push_back({"line_reacquired_events", behavior_.line_reacquired_events()});
  out.push_back({"reversed_sightings", behavior_.reversed_sightings()});
  out.push_back({"obstacles_avoided", behavior_.obstacles_avoided()});
  out.push_back({"tape_pieces_taken", pieces_taken_});
  out.push_back({"tape_pieces_refused", pieces_refused_});
}

}  // namespace carril::fw
