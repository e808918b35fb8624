#pragma once
// The follow_line mission as an explicit state machine: START, FOLLOW, SEARCH, AVOID, END, FAULT,
// each with named phases. Pure logic over one tick's inputs: no I/O, no heap, so unit tests can
// drive every transition with scripted observations.
#include <cstdint>

#include "firmware/behavior/BypassPlanner.hpp"
#include "firmware/behavior/LineState.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/control/PathTracker.hpp"
#include "firmware/core/Faults.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/perception/TapeMap.hpp"

namespace carril::fw {

// Sub-states of the mission states (START: wait, find, approach, align; FOLLOW: track; SEARCH:
// left, right, back; AVOID: stop, align, bypass, back_out, rejoin; END: approach, stopped; FAULT:
// stopped).
enum class Phase : std::uint8_t {
  Wait,
  Find,
  Approach,
  Align,
  Track,
  Left,
  Right,
  Back,
  Stop,
  Bypass,
  BackOut,  // AVOID: the lane turned out blocked; back to where the bypass left the tape
  Rejoin,
  Stopped,
  Reveal,  // END: the tape ran out by a mark seen only cut by the image's edge; back up to see it
  Count
};

inline const char* phase_name(Phase p) {
  static constexpr const char* kNames[] = {"wait",     "find",   "approach", "align", "track",
                                           "left",     "right",  "back",     "stop",  "bypass",
                                           "back_out", "rejoin", "stopped",  "reveal"};
  static_assert(sizeof(kNames) / sizeof(kNames[0]) == std::size_t(Phase::Count));
  return kNames[std::size_t(p)];
}

struct BehaviorConfig {
  double init_timeout_s = 3.0;         // drives and sensors must be up by then [s]
  double search_yaw_rate_radps = 0.6;  // turning speed while searching [rad/s]
  double start_max_turn_rad = 6.4;     // START gives up after a full turn without tape [rad]
  int lost_frames = 3;                 // frames without tape (and no tape left in memory)
  // Remembered tape that no frame has confirmed over this distance, or this long, is not
  // trusted any more: more than the camera's blind zone plus a corner pivot.
  double memory_trust_m = 1.2;            // [m]
  double memory_trust_s = 8.0;            // [s]
  double pid_lost_grace_s = 1.0;          // pid turns toward the last error this long first [s]
  double end_approach_m = 0.9;            // switch to END when the mark is this close [m]
  double end_speed_mps = 0.25;            // [m/s]
  double end_gain = 1.5;                  // approach speed per metre to the mark [1/s]
  double end_tolerance_m = 0.005;         // stop this close to the mark [m]
  double align_tolerance_rad = 0.04;      // heading alignment done within this [rad]
  double start_on_tape_lateral_m = 0.15;  // visible tape this close to the centre line ...
  double start_on_tape_angle_rad = 0.5;   // ... and this well aligned: already on the tape
  // Tape seen again within this distance of the tape remembered when it was lost is that same
  // tape, and must run the way the robot was travelling along it [m].
  double reacquire_on_path_m = 0.3;
  // A known end mark this close when the tape runs out is where the tape ends: drive onto it
  // rather than search (a short tail after a corner may never fill the camera's view) [m].
  double end_reach_m = 2.0;
  // The tape runs out with no end mark known, but one was glimpsed cut by the image's edge (it
  // came into view from the side in a turn onto a short last leg, and was under the camera's
  // blind zone once the robot faced it) within this distance: back up, once, at most this far,
  // until it is wholly in view [m].
  double end_reveal_m = 1.0;
  AvoidConfig avoid;

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<BehaviorConfig>> params();
  Status validate() const;
  bool operator==(const BehaviorConfig&) const = default;
};

// One tick's view of the world, assembled by FollowLineMission from the data bus.
struct BehaviorInput {
  double t_s = 0.0;
  bool drives_ready = false;
  bool camera_ready = false;      // a frame has arrived
  bool scanner_ready = false;     // a scan has arrived (or no lidar is fitted)
  bool imu_ready = true;          // a valid IMU sample has arrived (or no IMU is fitted)
  bool fresh_frame = false;       // a frame was processed this tick
  bool line_visible = false;      // the newest frame shows tape
  Vec2 line_near = Vec2::Zero();  // nearest visible tape point, robot frame [m]
  double line_near_angle = 0.0;   // tape direction there, relative to the robot's x [rad]
  bool fresh_scan = false;        // a scan was processed this tick
  bool obstacle_ahead = false;    // the mission runner sees an obstacle ahead (asked in FOLLOW)
  TrackState track;               // the robot against the remembered tape
  // The farthest remembered stretch of tape (where it runs into an obstacle, if one stands on
  // it), odometry frame; FollowLineMission finds it only when obstacle_ahead.
  bool tape_far_valid = false;
  Vec2 tape_far_point = Vec2::Zero();
  double tape_far_heading = 0.0;
  bool end_known = false;                // an end mark has been seen
  Vec2 end_odom = Vec2::Zero();          // its position, odometry frame [m]
  bool end_glimpsed = false;             // an end mark cut by the image's edge has been seen
  Vec2 end_glimpse_odom = Vec2::Zero();  // its visible part's centroid, odometry frame [m]
  Pose2 odom;
  Twist measured;  // from the wheel encoders
  const ObstacleField* obstacles = nullptr;
  const TapeMap* tape = nullptr;  // the remembered tape, in path order (nullptr: none kept)
  const RollingGrid<std::uint8_t>* costmap = nullptr;  // master costmap (nullptr: none built)
  bool costmap_updated = false;  // the costmap was rebuilt since the last tick
};

struct BehaviorOutput {
  Twist twist;
  bool clear_map = false;  // forget the remembered tape (after a search or a bypass)
  // With clear_map, after a bypass: the tape's line is still what it was before the obstacle,
  // so what was remembered stays the context small pieces of tape are judged against.
  bool rejoined = false;
  Fault fault = Fault::None;
};

class LineBehavior {
 public:
  LineBehavior(const BehaviorConfig& cfg, LineController& line, const BypassPlanner& planner,
               bool holonomic);

  // Starts the mission clock at `t_s` with the robot heading `yaw` [rad] (else the first step
  // does).
  void begin(double t_s, double yaw);
  BehaviorOutput step(const BehaviorInput& in, double dt_s);

  LineState state() const { return state_; }
  const char* phase() const { return phase_name(phase_); }
  bool end_done() const { return end_done_; }
  // END is still looking for the mark (backing up to see it whole), not yet driving onto it.
  bool end_revealing() const { return state_ == LineState::End && phase_ == Phase::Reveal; }
  std::uint32_t line_lost_events() const { return line_lost_; }
  std::uint32_t line_reacquired_events() const { return line_reacquired_; }
  // Sightings rejected in SEARCH because they ran against the remembered direction of travel.
  std::uint32_t reversed_sightings() const { return reversed_sightings_; }
  std::uint32_t obstacles_avoided() const { return obstacles_avoided_; }
  const BypassPlan& bypass() const { return plan_; }
  // Phase changes since the last call (a new phase name), for the event log.
  const char* take_phase_change();

 private:
  void enter(LineState s, Phase phase, double t_s);
  void set_phase(Phase phase);
  BehaviorOutput start(const BehaviorInput& in);
  BehaviorOutput follow(const BehaviorInput& in, double dt);
  BehaviorOutput search(const BehaviorInput& in);
  BehaviorOutput avoid(const BehaviorInput& in);
  BehaviorOutput end(const BehaviorInput& in);
  void begin_search(const BehaviorInput& in);
  // The tape in view lies on the tape remembered at the loss but points back along it.
  bool sighting_runs_backwards(const BehaviorInput& in) const;
  // The end mark is known and close enough to be where the tape ends.
  bool end_within_reach(const BehaviorInput& in) const;

  BehaviorConfig cfg_;
  LineController& line_;
  const BypassPlanner& planner_;
  PathTracker path_;
  LineState state_ = LineState::Start;
  Phase phase_ = Phase::Wait;
  bool phase_changed_ = false;
  double since_s_ = 0.0;
  bool started_ = false;
  int frames_without_line_ = 0;
  double line_seen_s_ = 0.0;          // when a frame last showed tape
  Vec2 line_seen_at_ = Vec2::Zero();  // and where the robot was then (odometry frame)
  double no_track_since_s_ = -1.0;
  double turned_ = 0.0, last_yaw_ = 0.0;  // accumulated turning in START / SEARCH [rad]
  double search_origin_yaw_ = 0.0;
  StaticVector<Vec2, TapeMap::kMaxPoints> lost_path_;  // remembered tape at the loss, odometry
  double align_heading_ = 0.0;
  Vec2 align_point_ = Vec2::Zero();
  Vec2 start_target_ = Vec2::Zero();  // odometry frame
  BypassPlan plan_;
  std::size_t waypoint_ = 0;
  // A bypass whose lane turns out blocked backs out along these (odometry frame) to where it
  // left the tape and tries the other side, once: excluded_side_ is the side given up (0 none).
  StaticVector<Vec2, 2> back_out_;
  std::size_t back_out_index_ = 0;
  int excluded_side_ = 0;
  double blocked_since_s_ = -1.0;
  bool end_done_ = false;
  bool reveal_tried_ = false;        // END's reveal is tried once per mission
  Vec2 reveal_from_ = Vec2::Zero();  // where it started (odometry frame)
  std::uint32_t line_lost_ = 0, line_reacquired_ = 0, obstacles_avoided_ = 0;
  std::uint32_t reversed_sightings_ = 0;
};

}  // namespace carril::fw
