#pragma once
// The follow_line mission: follow the tape from wherever it is found to the end mark, searching
// when it is lost and passing obstacles that stand on it. Its state machine is LineBehavior
// (START, FOLLOW, SEARCH, AVOID, END, FAULT); this class feeds it from the data bus, keeps the
// tape seen so far (TapeMap, odometry frame) and where the end mark is, and reports it through
// the Mission interface.
#include "firmware/behavior/BypassPlanner.hpp"
#include "firmware/behavior/LineBehavior.hpp"
#include "firmware/control/LineController.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mission/Mission.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/perception/LinePerception.hpp"
#include "firmware/perception/TapeMap.hpp"

namespace carril::fw {

struct FollowLineConfig {
  StrategyConfig strategy;  // which follower, its gains and the cruise speed
  BehaviorConfig behavior;  // state machine and obstacle avoidance
  double tape_preview_m =
      0.6;  // how far ahead along the remembered tape corners are looked for [m]

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<FollowLineConfig>> params();
  Status validate() const;
  bool operator==(const FollowLineConfig&) const = default;
};

class FollowLineMission final : public Mission {
 public:
  FollowLineMission(const FollowLineConfig& cfg, const Footprint& footprint, bool holonomic,
                    bool lidar_present, const Topic<OdometryMsg>& odom,
                    const Topic<LineObservation>& line, const Topic<ObstacleField>& obstacles);

  const char* name() const override { return "follow_line"; }
  void enter(const MissionContext& ctx) override;
  void exit() override {}
  MissionOutput update(const MissionContext& ctx) override;
  MissionState state() const override;
  const char* take_phase_change() override { return behavior_.take_phase_change(); }
  void counters(MissionCounters& out) const override;
  // Frames whose only tape was a piece smaller than tape on its own, taken because it continued
  // the remembered tape, and refused because it did not.
  std::uint32_t pieces_taken() const { return pieces_taken_; }
  std::uint32_t pieces_refused() const { return pieces_refused_; }

  const LineBehavior& behavior() const { return behavior_; }
  const TapeMap& tape() const { return map_; }
  // The costmap the bypass is checked on (no view on it: the obstacle outline alone decides).
  void watch_costmap(const Topic<CostmapMsg>& c) { costmap_in_.watch(c); }

 private:
  // Tape and end mark of a new frame into memory; whether the frame showed tape.
  bool remember(const LineObservation& obs);
  BehaviorInput inputs(const MissionContext& ctx);

  FollowLineConfig cfg_;
  bool lidar_present_;
  LineController line_;
  BypassPlanner planner_;
  LineBehavior behavior_;
  TapeMap map_;
  // The tape remembered before a bypass cleared memory, while memory is empty again: a piece
  // too small to be tape on its own counts where it continues this (the tape beyond the
  // obstacle, on the line the bypass assumed).
  TapeMap before_bypass_;
  const Topic<OdometryMsg>& odom_;
  Reader<LineObservation> obs_;
  Reader<ObstacleField> obstacles_;
  bool end_known_ = false;
  bool end_glimpsed_ = false;             // an end mark cut by the image edge has been seen
  Vec2 end_glimpse_odom_ = Vec2::Zero();  // the visible part's centroid, odometry frame [m]
  CostmapInput costmap_in_;               // no view: none built
  const CostmapView* costmap() const { return costmap_in_.view(); }
  std::uint32_t costmap_seen_ = 0;
  Vec2 end_odom_ = Vec2::Zero();
  bool line_seen_ = false;  // the newest frame showed tape (LineDetection::sure, or a piece of it)
  std::uint32_t pieces_taken_ = 0, pieces_refused_ = 0;
};

}  // namespace carril::fw
