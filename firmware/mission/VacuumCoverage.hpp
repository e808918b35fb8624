#pragma once
// The vacuum coverage mission (mode: vacuum): the course's reactive state machine as a baseline,
// blind to the map; on a map it counts what it swept of the reachable area as the systematic
// mission does (CoverageMission).
//   SPIRAL --bump--> BACK_UP --timer--> TURN (random direction and time) --timer--> FORWARD
//   FORWARD --bump--> BACK_UP; FORWARD --timer--> SPIRAL; SPIRAL --spiral_max_s--> FORWARD
// A bump is a lethal costmap cell just ahead of the body, or the obstacle guard's stop corridor.
#include "firmware/mission/CoverageMission.hpp"

namespace carril::fw {

class VacuumCoverage final : public CoverageMission {
 public:
  VacuumCoverage(const CoverageConfig& cfg, const Footprint& footprint,
                 const Topic<OdometryMsg>& pose, const Topic<CostmapMsg>& costmap,
                 const OccupancyGrid& static_map)
      : CoverageMission(cfg, footprint, pose, costmap, static_map) {}

 private:
  void restart() override;
  MissionOutput step(const MissionContext& ctx, const Pose2& pose) override;
  MissionOutput begin(const Pose2& pose) override;
  MissionOutput planned(const Pose2&) override { return {}; }  // it plans nothing but the area

  bool bumped(const MissionContext& ctx, const Pose2& pose) const;
  double uniform();

  std::uint32_t rng_ = 1;
  double turn_s_ = 0.0, turn_dir_ = 1.0;
};

}  // namespace carril::fw
