#pragma once
// The systematic coverage mission (mode: systematic): the area's boustrophedon decomposition
// driven cell by cell along its tour, transits planned on the static map and the costmap, lanes
// cut where the lidar sees what the map does not show and resumed past it, revisits of what is
// left. The state machine is in CoverageMission.hpp's comment; the shared frame (area, accounting,
// reachable area, time limit) is CoverageMission's.
#include "firmware/mission/CoverageMission.hpp"
#include "firmware/mission/PathChecks.hpp"

namespace carril::fw {

class SystematicCoverage final : public CoverageMission {
 public:
  static constexpr std::size_t kMaxRoute = 4096;      // waypoints of one cell's lanes
  static constexpr std::size_t kMaxPathCells = 4096;  // cells of one transit path
  static constexpr std::size_t kMaxWaypoints = 1024;  // waypoints of one transit path

  // The shared area, then its decomposition and tour and the revisits' buffers (init time).
  SystematicCoverage(const CoverageConfig& cfg, const Footprint& footprint, bool holonomic,
                     const Topic<OdometryMsg>& pose, const Topic<CostmapMsg>& costmap,
                     const OccupancyGrid& static_map);

  const Boustrophedon& decomposition() const { return bcd_; }
  // The route left to sweep: n waypoints [m] from the returned one on.
  const Vec2* sweep_route(std::size_t& n) const {
    n = route_.size() - sweep_from_;
    return route_.begin() + sweep_from_;
  }

 private:
  void restart() override;
  MissionOutput step(const MissionContext& ctx, const Pose2& pose) override;
  MissionOutput begin(const Pose2& pose) override;
  MissionOutput planned(const Pose2& pose) override;

  void arrive(const Pose2& pose);
  // A new cell's sweep starting this far or more from its first point drives onto it first [m].
  static constexpr double kOnRouteM = 0.03;
  void start_route_here(const Pose2& pose);
  void finish_cell();
  // A joined cell's first lane runs at least this far before it turns again (unless it ends) [m].
  static constexpr double kJoinSettleM = 0.3;
  bool join_next_cell(const Pose2& pose);
  bool join_clear(std::size_t from, std::size_t to) const;
  bool pick_next_cell(const Pose2& pose);
  bool pick_resume(const Pose2& pose);
  bool pick_revisit(const Pose2& pose);
  std::int32_t reachable_anchor(std::size_t k, long& budget) const;
  bool path_to(int ti, int tj, const Vec2& target);
  MissionOutput transit(const Pose2& pose);
  MissionOutput sweep(const Pose2& pose);
  MissionOutput spin(const Pose2& pose);
  MissionOutput reverse(const Pose2& pose);
  MissionOutput emergency_stop(const Pose2& pose);
  bool cut_lane(const Pose2& pose, const PathProjection& at);
  bool near_edge(const Vec2& p) const;
  bool path_blocked_ahead(const Pose2& pose) const;
  CellVisit tour_visit(std::size_t k) const;
  double swept_fraction(std::uint16_t cell) const;

  PathTracker tracker_;
  LaneFollower sweep_follower_;
  PurePursuitFollower transit_follower_;
  Boustrophedon bcd_;
  std::unique_ptr<std::uint8_t[]> abandoned_;     // revisit targets already tried
  std::unique_ptr<std::uint32_t[]> patch_size_;   // the unswept patch each unswept cell is in
  std::unique_ptr<std::uint32_t[]> patch_queue_;  // the flood fill's queue [cell indices]

  bool tour_reversed_ = false;
  std::size_t tour_pos_ = 0;
  CellVisit visit_;
  StaticVector<Vec2, kMaxRoute> route_;
  std::size_t sweep_from_ = 0;  // the route from here on is left to sweep
  bool join_tried_ = false;     // on the route's last lane, the next cell was looked at
  State after_transit_ = State::Sweep;
  StaticVector<GridCell, kMaxPathCells> cells_;
  StaticVector<Vec2, kMaxWaypoints> waypoints_;
  std::uint32_t seen_updates_ = 0;
  StopStreak stops_;
  Vec2 backup_from_{0.0, 0.0};
  double spun_rad_ = 0.0, spin_last_yaw_ = 0.0;
  Vec2 spin_at_{0.0, 0.0};  // where the revisit turns [m]
};

}  // namespace carril::fw
