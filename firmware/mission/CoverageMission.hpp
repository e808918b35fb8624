#pragma once
// The coverage (cleaning) missions: sweep the free space of the static map, or of a polygon of it,
// with a tool of tool_width across the robot. Two missions on one shared base (CoverageMission,
// below), picked by the mission file's `mode:`:
//
// systematic (SystematicCoverage.hpp): the area's boustrophedon decomposition
// (firmware/planning/Boustrophedon.hpp, built at init from the static map eroded by the robot's
// radius) is driven cell by cell in the order of its tour, each cell's lanes with pure pursuit at
// cruise speed; transitions are planned with the wavefront planner on the static map overlaid with
// the live costmap (so they go through doors and round what the lidar sees). The mission marks its
// CoverageGrid from the localised pose every tick, so it knows what it really swept: a lane blocked
// by an obstacle the map does not show is cut short and resumed past it; a cell its neighbours'
// lanes already swept is skipped; each cell is entered at the corner nearest the robot. Where the
// tour's next cell begins with a lane across from the end of the cell's last one, at the same end
// and driven the other way, the sweep turns into it by a U-turn as between its own lanes (a join:
// no plan, transit or turns on the spot). After the last cell it goes back for what is left
// (REVISIT: to the unswept cell nearest by the planner of a patch of at least revisit_min_area_m2,
// a half turn and more on the spot there, each cell tried once) until target_coverage of the cells
// reachable now is swept (cells an unmapped obstacle seals off do not count) or nothing reachable
// is left. It does not call the job complete when it is not: covered_permille is what it swept of
// the whole area.
//
//   WAIT --drives ready, costmap built--> PLAN(initial: reachable area, tour direction)
//   PLAN(next cell) --path--> TRANSIT --at the cell's corner--> SWEEP --end of its lanes--> PLAN
//   SWEEP --on its last lane, the next cell joined--> SWEEP (the next cell's lanes)
//   SWEEP --obstacle on the lane ahead--> PLAN(resume past it) --> TRANSIT --> SWEEP
//   PLAN(next cell) --no cell left--> PLAN(revisit) --> TRANSIT --> SPIN --> PLAN(revisit)
//   PLAN(revisit) --target coverage reached, or no reachable unswept cell--> DONE
//   TRANSIT --a lethal cell just ahead, the path straight on--> REVERSE --> PLAN (same target)
//   WAIT/PLAN --no free cell to cover--> FAILED (no_coverage_area); --nothing reachable--> FAILED
//   (no_path)
//
// vacuum (VacuumCoverage.hpp): the course's reactive state machine as a baseline, blind to the map:
//   SPIRAL --bump--> BACK_UP --timer--> TURN (random direction and time) --timer--> FORWARD
//   FORWARD --bump--> BACK_UP; FORWARD --timer--> SPIRAL; SPIRAL --spiral_max_s--> FORWARD
// A bump is a lethal costmap cell just ahead of the body, or the obstacle guard's stop corridor.
//
// The body is taken as its inscribed circle throughout (the area's erosion, the costmap's
// inscribed cells, the checks ahead), so a square body's corners may brush a wall in a turn.
// Counters: cells, lanes (of the cells finished), lanes_blocked, revisits, bumps, replans,
// covered_permille, overlap_permille (of the reachable coverable cells, CoverageArea), joins.
//
// Both stop after max_time_s (DONE, phase "time_limit"). Every tick's work is bounded: the heavy
// work (erosion, decomposition, gaps, tour) runs in the constructor; planning spreads the
// wavefront over ticks (plan_expansions_per_tick); a tick copies the costmap at most once.
#include <cstdint>
#include <memory>

#include "firmware/control/LaneFollower.hpp"
#include "firmware/control/PathTracker.hpp"
#include "firmware/control/PurePursuitFollower.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mapping/CoverageGrid.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "firmware/mission/Mission.hpp"
#include "firmware/mission/MissionPhase.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/planning/Boustrophedon.hpp"
#include "firmware/planning/CoverageArea.hpp"
#include "firmware/planning/WavefrontPlanner.hpp"

namespace carril::fw {

enum class CoverageMode : std::uint8_t { Systematic, Vacuum };

// The reactive baseline's timers and speeds.
struct VacuumConfig {
  double spiral_speed_mps = 0.3;       // along the spiral [m/s]
  double spiral_start_radius_m = 0.1;  // [m]
  double spiral_growth_mps = 0.01;     // the radius grows this fast [m/s]
  double spiral_max_s = 60.0;          // then FORWARD [s]
  double backup_s = 1.0;               // BACK_UP time [s]
  double backup_speed_mps = 0.15;      // [m/s]
  double turn_min_s = 0.5;             // TURN lasts a random time in [turn_min_s, turn_max_s] [s]
  double turn_max_s = 2.5;             // [s]
  double turn_rate_radps = 1.0;        // [rad/s]
  double forward_speed_mps = 0.4;      // [m/s]
  double forward_s = 15.0;             // FORWARD without a bump this long: SPIRAL again [s]
  double bump_m = 0.03;                // a lethal cell this close ahead of the body: a bump [m]

  Status validate() const;
  bool operator==(const VacuumConfig&) const = default;
};

struct CoverageConfig {
  CoverageMode mode = CoverageMode::Systematic;
  double tool_width_m = 0.5;       // the tool's width across the robot [m]
  double speed_mps = 0.4;          // cruise speed on the lanes [m/s]
  double transit_speed_mps = 0.4;  // cruise speed between cells [m/s]
  // Above speed_mps only where no cell within this margin of the robot's centre, nor of the
  // point transit_edge_lookahead_m ahead of it, is off the static area [m]
  double transit_edge_margin_m = 0.1;
  double transit_edge_lookahead_m = 0.25;  // [m]
  double lane_overlap = 0.1;               // lanes are tool_width * (1 - lane_overlap) apart [-]
  double turn_radius_m = 0.0;  // U-turn arcs between lanes; 0: half the lane spacing [m]
  // A cell whose first lane starts this close across from the end of the last lane of the cell
  // being swept, at the same end and driven the other way, is joined to it by a U-turn as the
  // lanes' own instead of a transit; 0: never [m]
  double join_max_gap_m = 1.0;
  // ...with the two lanes' ends at most this far apart along them [m]
  double join_max_step_m = 0.1;
  // The lanes and transits keep this much beyond the inscribed radius from the walls and from
  // obstacles the map does not show [m]
  double wall_clearance_m = 0.0;
  StaticVector<Vec2, 16> area;       // the area's polygon, map frame [m]; empty: the whole map
  double target_coverage = 0.97;     // REVISIT ends at this covered fraction of the area [-]
  double skip_swept_cell = 0.98;     // a cell this much swept already (from its neighbours' lanes)
                                     // is not visited [-]
  std::uint32_t max_revisits = 200;  // REVISIT ends after this many targets [targets]
  // A revisit goes only for a patch of unswept cells (8-connected) at least this large: a trip of
  // a plan, a transit and a turn on the spot costs more than a scallop of a few cells by a wall
  // is worth; 0: any cell [m^2]
  double revisit_min_area_m2 = 0.05;
  double revisit_spin_rad = 3.3;  // turned on the spot at a revisit target [rad]
  double spin_rate_radps = 1.0;   // that turn's rate [rad/s]
  double max_time_s = 1800.0;     // the mission ends (DONE) after this long; 0: never [s]
  std::uint32_t seed = 1;         // the vacuum's random turns
  VacuumConfig vacuum;

  LaneFollowerConfig sweep;           // on the lanes and their U-turns
  PurePursuitConfig transit_pursuit;  // between cells
  PathTrackerConfig tracker;          // turning on the spot
  WavefrontConfig planner;
  std::uint32_t plan_expansions_per_tick = 2000;  // the planner's budget per tick [cells]
  double block_lookahead_m = 0.6;        // an obstacle on the lane this far ahead cuts it [m]
  double resume_clear_m = 0.4;           // a lane resumes where it is clear this far on [m]
  double replan_lookahead_m = 3.0;       // an obstacle on a transit path this far ahead: replan [m]
  double emergency_stop_m = 0.03;        // a lethal cell this close ahead of the body stops [m]
  double backup_m = 0.2;                 // reversed after such a stop [m]
  double backup_speed_mps = 0.1;         // [m/s]
  std::uint32_t max_recoveries = 5;      // stops in a row before the target is given up [stops]
  double turn_in_place_min_radps = 0.2;  // a lethal cell ahead while turning: turn in place
  // A lethal costmap cell this close to a wall of the static map is that wall (the lidar's
  // returns off a wall's face land in the free cell before it about half the time): the static
  // area already keeps the robot clear of it. Farther ones are unmapped obstacles [m].
  double mapped_wall_tolerance_m = 0.1;
  std::uint32_t max_cells = 256;   // decomposition cells the buffers hold [cells]
  std::uint32_t max_lanes = 2048;  // lanes the buffers hold [lanes]

  CoverageConfig();
  Status validate() const;
  bool operator==(const CoverageConfig&) const = default;
};

// What the two coverage missions share (ArduPilot's mode base): the area and what was swept of
// it, the wavefront that finds the reachable area, the costmap's obstacles the map does not show,
// the frame of every tick (the sweep accounting, the time limit, the wait at the start), the
// state, phase and counters. SystematicCoverage and VacuumCoverage are the two missions; the
// mission file's `mode:` picks one (make_coverage_mission()).
class CoverageMission : public Mission {
 public:
  // Builds the area and the planner's buffers from the static map (init time). `pose` is the
  // localised pose in the map frame; the costmap indexes its cells as floor(x / resolution) in
  // the same frame. A failure is kept in init_status() and ends the mission at its first tick with
  // no_coverage_area.
  CoverageMission(const CoverageConfig& cfg, const Footprint& footprint,
                  const Topic<OdometryMsg>& pose, const Topic<CostmapMsg>& costmap,
                  const OccupancyGrid& static_map);

  const char* name() const override { return "coverage"; }
  void enter(const MissionContext& ctx) override;
  void exit() override {}
  MissionOutput update(const MissionContext& ctx) override;
  MissionState state() const override;
  const char* take_phase_change() override { return phase_.take_change(); }
  void counters(MissionCounters& out) const override;

  enum class State : std::uint8_t {
    Wait,
    Plan,
    Transit,
    Sweep,
    Spin,
    Reverse,
    Spiral,
    BackUp,
    Turn,
    Forward,
    Done,
    Failed,
  };
  State current() const { return state_; }
  // Why the mission cannot run (ok when it can).
  const Status& init_status() const { return init_status_; }
  // What it swept, on the static map's cells (mask: the reachable coverable cells).
  const CoverageGrid& coverage() const { return coverage_; }
  const CoverageArea& area() const { return area_; }
  std::uint32_t bumps() const { return bumps_; }
  std::uint32_t joins() const { return joins_; }  // cells joined onto the one before [cells]
  std::uint32_t turns_left() const { return turns_left_; }
  std::uint32_t turns_right() const { return turns_right_; }

 protected:
  enum class Purpose : std::uint8_t { Initial, NextCell, Resume, Revisit };

  // The mission's own part of enter(): its state back to the start.
  virtual void restart() = 0;
  // One tick in one of the mission's own states (neither Wait, Plan, Done nor Failed).
  virtual MissionOutput step(const MissionContext& ctx, const Pose2& pose) = 0;
  // The reachable area is known (or, off a map, cannot be): the mission begins.
  virtual MissionOutput begin(const Pose2& pose) = 0;
  // A plan for `purpose_` (not Initial) has finished expanding: pick its target.
  virtual MissionOutput planned(const Pose2& pose) = 0;

  void go(State s, const char* phase);
  MissionOutput fail(Fault f);
  std::size_t cell_index(int i, int j) const;
  MissionOutput start_plan(Purpose p, const Pose2& pose);
  MissionOutput next_plan(Purpose p);  // planning starts at the next tick
  MissionOutput plan_step(const Pose2& pose);
  // obstacles the map does not show (CoverageObstacles.cpp)
  void build_mapped_mask();
  bool unmapped_lethal(int cx, int cy) const;
  void overlay_unmapped();
  double obstacle_reach_m() const;
  bool blocked_at(const Vec2& p) const;
  // any_lethal: every lethal cell counts (the vacuum is blind to the map), else unmapped ones.
  bool lethal_near(const Pose2& pose, double margin, bool forward, bool any_lethal) const;
  const CostmapView& costmap() const { return costmap_in_.get(); }

  CoverageConfig cfg_;
  Footprint footprint_;
  const Topic<OdometryMsg>& pose_;
  // The costmap (its view, published at init by Mapping; validate() requires one).
  CostmapInput costmap_in_;
  const OccupancyGrid& map_;
  Status init_status_;
  bool accounting_ = false;  // the map is usable: the coverage grid counts
  CoverageArea area_;
  CoverageGrid coverage_;
  WavefrontPlanner planner_;
  std::unique_ptr<std::uint8_t[]> base_costs_;  // the static area: 0 on centre cells, else lethal
  std::unique_ptr<std::uint8_t[]> plan_costs_;  // base_costs_ overlaid with the costmap
  std::unique_ptr<std::uint8_t[]> mapped_;      // within mapped_wall_tolerance_m of a wall

  State state_ = State::Wait;
  MissionPhase phase_;
  double now_s_ = 0.0, t0_s_ = -1.0,
         state_t0_s_ = 0.0;  // this tick, the start, the state's start [s]
  bool have_last_ = false;
  Pose2 last_pose_;
  Purpose purpose_ = Purpose::Initial;
  bool planning_ = false;  // the wavefront of this PLAN has been started

  std::uint32_t cells_done_ = 0, lanes_ = 0, lanes_blocked_ = 0, revisits_ = 0, bumps_ = 0,
                replans_ = 0, turns_left_ = 0, turns_right_ = 0, joins_ = 0;
  Fault fault_ = Fault::None;
};

// The mission of cfg.mode: a SystematicCoverage or a VacuumCoverage (init time).
std::unique_ptr<CoverageMission> make_coverage_mission(const CoverageConfig& cfg,
                                                       const Footprint& footprint, bool holonomic,
                                                       const Topic<OdometryMsg>& pose,
                                                       const Topic<CostmapMsg>& costmap,
                                                       const OccupancyGrid& static_map);

const char* coverage_state_name(CoverageMission::State s);

}  // namespace carril::fw
