#pragma once
// Is a pose the only one that explains a scan? Among alike warehouse aisles (or city blocks) a
// scan fits the map about as well one aisle over, and a filter that converges on either is
// localised by chance. AliasSearch scores one scan (coarse_beams of its beams) at every candidate
// position of the map (a grid of `stride_m` over the cells the robot's centre may stand on) at
// the pose's heading, keeps the
// best few at least `min_separation_m` from the pose, and refines them and the pose itself by a
// local pattern search (x, y and yaw) with all max_beams. Besides the pose's heading it tries
// `headings` - 1 more, evenly spaced round the circle, at every position: a symmetric layout also
// fits a scan turned half round (a pose 1.3 m off and 180 deg turned, in the warehouse's cross
// aisle). The pose is ambiguous when an alias fits within `margin` (mean log p per beam) of the
// pose's own fit.
//
// The likelihood field is the one the fit checks use (MonteCarloLocalizer::scan_fit); the beams are
// the same ones (ScanBeams.hpp). A search is begun with a scan and carried out by step() calls,
// each bounded in field lookups, so it spreads over control ticks. Every buffer is sized in the
// constructor; nothing allocates afterwards.
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/estimation/LikelihoodField.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct AliasSearchConfig {
  double stride_m = 0.1;          // spacing of the candidate positions [m]
  int headings = 4;               // headings tried, the pose's and evenly spaced others
  double min_separation_m = 1.0;  // an alias at the pose's heading lies this far from it [m]
  double clearance_m = 0.15;      // candidates only this far or more from an occupied cell [m]
  double margin = 0.1;            // an alias this close to the pose's fit makes it ambiguous
                                  // [log(1/m) per beam]
  int max_beams = 60;             // beams scored (evenly spaced valid ones, as the filter's)
  int coarse_beams = 20;          // of those, evenly spaced ones the candidate pass scores
  // A refined alias counts only if at most this fraction of the scan's returns, seen from it,
  // pass through the map's walls (BeamsThroughWalls.hpp, walked from margin past the sensor to
  // margin short of the return): the likelihood scores where beams end, so a room whose
  // partitions the scan would cross fits as well but is no alias (1: not checked) [-], [m].
  double max_through_fraction = 1.0;
  double through_margin_m = 0.3;
  double max_range_m = 12.0;  // returns at or beyond are not scored [m]

  Status validate() const;
  bool operator==(const AliasSearchConfig&) const = default;
};

struct AliasResult {
  double own_fit = 0.0;    // the pose's fit after refinement [log(1/m) per beam]
  double alias_fit = 0.0;  // the best alias's fit (-inf when no candidate) [log(1/m) per beam]
  Pose2 pose;              // the pose, refined [m, m, rad]
  Pose2 alias;             // the best alias, refined [m, m, rad]
  bool ambiguous = false;  // alias_fit >= own_fit - margin
};

class AliasSearch {
 public:
  // Best aliases kept from the coarse pass for refinement.
  static constexpr int kKeep = 16;

  // Lists the candidate positions of `map` (init time). field and map must outlive this.
  AliasSearch(const AliasSearchConfig& cfg, const LikelihoodField& field, const OccupancyGrid& map);

  const Status& status() const { return status_; }
  int candidate_count() const { return n_cand_; }

  // Begins a search for a scan seen from map pose `pose` (the scanner at laser_mount in the robot
  // frame). false if the scan has no valid beam or the object is unusable; a search under way is
  // dropped.
  bool begin(const hal::LaserScan& scan, const Pose2& pose, const Pose2& laser_mount);
  // Works for about `lookups` field lookups; true while the search is still running.
  bool step(long lookups);
  bool busy() const { return phase_ != Phase::Idle; }
  void abort() { phase_ = Phase::Idle; }
  // Completed searches since construction; result() is the latest's.
  std::uint64_t completed() const { return completed_; }
  const AliasResult& result() const { return result_; }

 private:
  enum class Phase : std::uint8_t { Idle, Scan, Refine };
  struct Kept {
    float gx = 0.0F, gy = 0.0F;  // padded grid coordinates
    float score = 0.0F;          // sum of log p
    int heading = 0;             // index of the heading tried
  };

  float score(float gx, float gy, double yaw) const;
  double heading_yaw(int k) const;  // the pose's yaw + k turns of 2 pi / headings [rad]
  void keep(float gx, float gy, float s, int heading);
  // Pattern search from p; returns the refined pose, its sum of log p in `best`, and adds the
  // poses it scored to `scored`.
  Pose2 refine(const Pose2& p, float& best, long& scored) const;
  Pose2 world(float gx, float gy, double yaw) const;
  // Whether the scan seen from pose passes the walls check (max_through_fraction); adds its cost
  // to `scored` in poses' worth.
  bool passes_walls_check(const Pose2& pose, long& scored) const;

  AliasSearchConfig cfg_;
  Status status_;
  const LikelihoodField& field_;
  const OccupancyGrid& map_;
  hal::LaserScan scan_;  // the search's scan, for the walls check
  Pose2 mount_;
  double inv_res_ = 20.0, gx0_ = 1.0, gy0_ = 1.0;  // world -> padded grid coordinates
  std::unique_ptr<std::uint16_t[]> cand_;          // candidate cells, (i, j) pairs
  int n_cand_ = 0;
  std::unique_ptr<float[]> bx_, by_;  // beam endpoints in the robot frame [cells]
  int nb_ = 0;
  std::unique_ptr<float[]> cbx_, cby_;  // the candidate pass's subset of them
  int ncb_ = 0;

  Phase phase_ = Phase::Idle;
  int cursor_ = 0;
  Pose2 pose_;
  float pgx_ = 0.0F, pgy_ = 0.0F;  // the pose in padded grid coordinates
  int heading_ = 0;                // heading of the candidate pass under way
  float min_sep2_ = 0.0F;          // [cells^2]
  Kept kept_[kKeep];
  int n_kept_ = 0;
  float best_alias_ = 0.0F;
  Pose2 best_alias_pose_;
  AliasResult result_;
  std::uint64_t completed_ = 0;
};

}  // namespace carril::fw
