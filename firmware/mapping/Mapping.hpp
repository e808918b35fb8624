#pragma once
// Component: the robot-centred costmap. A new 2D scan goes into the obstacle layer. Without
// terrain the window follows the robot every tick and the master (layers combined and inflated,
// what the missions read through CostmapView) is rebuilt at master_rate_hz. With terrain, one
// cycle per 3D lidar sweep, a bounded piece of it per tick so that no tick carries a whole
// sweep or a whole window: the windows move and the sweep begins with the pose of its stamp,
// its points are binned a slice per tick, the binned cells are fused a slice per tick, the
// terrain analysis and the profile's traversability layer run a strip of rows per tick, then the
// master is rebuilt. Between, the master is rebuilt at master_rate_hz too (fresh obstacles, the
// traversability as far as the analysis got, all on one window). A tick does one piece only: a
// scan, a master rebuild or a terrain piece.
//
// On a known map (a static OccupancyGrid given), the costmap is in the map frame instead, read
// with the localised pose: one window covering the whole map that never moves, the map's walls
// as a static layer under the live obstacles (like Nav2's global costmap), no terrain. Scans are
// marked only while the pose is localised, and when it is regained after being lost (it may have
// jumped) the obstacle layer is forgotten: marks made from a wrong pose are phantom walls.
#include <cstdint>

#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/SampleReader.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/mapping/ElevationLayer.hpp"
#include "firmware/mapping/LayeredCostmap.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "firmware/mapping/Pose3Tracker.hpp"
#include "firmware/mapping/StaticLayer.hpp"
#include "firmware/mapping/TerrainAnalysis.hpp"
#include "firmware/mapping/TraversabilityLayer.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/CostmapView.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct MappingConfig {
  bool enabled = false;  // build a costmap at all (goto needs one; follow_line uses it to avoid)
  CostmapConfig costmap;
  double master_rate_hz = 5.0;  // master rebuilds per second [Hz]
  // Terrain: a 3D lidar is fitted and the traversability layer is built from it.
  bool terrain = false;
  SensorMount lidar3d;
  ElevationConfig elevation;
  TerrainConfig analysis;
  TraversabilityProfile profile;
  double start_free_radius_m = 1.5;  // the blind zone round the start pose, free at start [m]
  int terrain_rows_per_tick = 4;     // analysed per tick [rows]
  int fuse_points_per_tick = 4000;   // 3D points binned per tick [points]
  int fuse_cells_per_tick = 2000;    // binned cells fused into the elevation map per tick [cells]

  Status validate() const;
  bool operator==(const MappingConfig&) const = default;
};

// The costmap window for a known map: the map's resolution, its extent plus a cell on each side
// (the map's origin need not fall on a cell boundary), the rest of cfg kept.
CostmapConfig costmap_for_map(const CostmapConfig& cfg, const MapInfo& map);

struct MappingTelemetry {
  std::uint32_t scans = 0;              // 2D scans integrated
  std::uint32_t sweeps = 0;             // 3D sweeps fused
  std::uint32_t sweeps_abandoned = 0;   // sweeps replaced by a newer one while being binned
  std::uint32_t master_updates = 0;     // master rebuilds
  std::uint32_t skipped_master = 0;     // rebuilds skipped (a layer on another window)
  std::uint32_t scans_unlocalised = 0;  // scans not marked: the pose was not localised
  std::uint32_t obstacle_clears = 0;    // obstacle layer forgotten on a relocalisation
  double z_m = 0.0;                     // the robot's height from the IMU pitch [m]
};

class Mapping final : public CostmapView {
 public:
  // Allocates every grid (init time). cfg must have passed validate(). pose is the robot's pose
  // in the costmap's frame: odometry, or on a known map (static_map non-null, not empty, and
  // outliving this) the localised pose in the map frame. When enabled, publishes itself on
  // costmap (if given) at once: the missions read the costmap through that topic.
  // lidar_mount: the 2D lidar in the robot frame (ObstacleSensingConfig::mount()) [m, m, rad].
  Mapping(const MappingConfig& cfg, double tick_rate_hz, const Pose2& lidar_mount,
          const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& pose,
          const OccupancyGrid* static_map = nullptr, Topic<CostmapMsg>* costmap = nullptr);

  // Task: one tick of mapping work (none when init failed).
  void run();
  // The first grid that could not be set up at init (ok when all were, or when disabled).
  const Status& init_status() const { return init_; }

  const RollingGrid<std::uint8_t>& master() const override { return costmap_.master(); }
  const RollingGrid<std::uint8_t>& obstacles() const override { return costmap_.obstacle_layer(); }
  const RollingGrid<std::uint8_t>* walls() const override {
    return static_map_ != nullptr ? &static_layer_.grid() : nullptr;
  }
  std::uint32_t updates() const override { return tel_.master_updates; }

  bool enabled() const { return cfg_.enabled; }
  const LayeredCostmap& costmap() const { return costmap_; }
  const ElevationLayer& elevation() const { return elevation_; }
  const TerrainAnalysis& analysis() const { return analysis_; }
  const TraversabilityLayer& traversability() const { return traversability_; }
  const Pose3& pose3() const { return pose3_.pose(); }
  const MappingTelemetry& telemetry() const { return tel_; }
  const MappingConfig& config() const { return cfg_; }
  // A known map is the static layer (the window then covers it and never moves).
  bool on_map() const { return static_map_ != nullptr; }
  const StaticLayer& static_layer() const { return static_layer_; }

 private:
  MappingConfig cfg_;
  Pose2 lidar_mount_;
  Status init_;
  // Keeps the first failure of an init step in init_; the step's success.
  bool take(const Status& s);
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  const OccupancyGrid* static_map_ = nullptr;
  StaticLayer static_layer_;
  LayeredCostmap costmap_;
  ElevationLayer elevation_;
  TerrainAnalysis analysis_;
  TraversabilityLayer traversability_;
  Pose3Tracker pose3_;
  bool started_ = false;
  std::uint32_t master_divisor_ = 1, tick_ = 0;
  SampleReader<hal::LaserScan> scans_;
  SampleReader<hal::PointCloud> clouds_;
  std::uint32_t seen_relocalisations_ = 0;
  // The robot's 3D pose over the last ticks: a sweep is fused with the pose of its stamp (a
  // driver delivers it after the sweep; fusing it with the current pose smears the map).
  struct StampedPose {
    hal::TimeNs t_ns = 0;
    Pose3 pose;
  };
  RingBuffer<StampedPose, 64> history_;
  Pose3 pose_at(hal::TimeNs t_ns) const;
  // The terrain cycle: each tick does the piece of its phase.
  enum class TerrainPhase : std::uint8_t { kWaitSweep, kBin, kFuse, kAnalyse, kMaster };
  TerrainPhase phase_ = TerrainPhase::kWaitSweep;
  std::uint32_t binning_seq_ = 0, next_point_ = 0;
  int next_row_ = 0;  // the analysis' next strip
  bool master_due_ = false;
  void terrain_piece(const SensorFrame& f);
  void rebuild_master();
  void begin_sweep(const hal::PointCloud& cloud, const Pose2& pose);
  MappingTelemetry tel_;
};

}  // namespace carril::fw
