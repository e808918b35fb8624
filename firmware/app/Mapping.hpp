#pragma once
// Component: the robot-centred costmap. A new 2D scan goes into the obstacle layer. Without
// terrain the window follows the robot every tick and the master (layers combined and inflated,
// what the missions read through CostmapView) is rebuilt at master_rate_hz. With terrain, one
// cycle per 3D lidar sweep: the windows move, the sweep is fused into the elevation map with the
// pose of its stamp, the terrain analysis and the profile's traversability layer run a strip of
// rows per tick (no tick carries a whole window), then the master is rebuilt.
#include <cstdint>

#include "firmware/core/Frames.hpp"
#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/estimation/WheelOdometry.hpp"
#include "firmware/mapping/CostmapView.hpp"
#include "firmware/mapping/ElevationLayer.hpp"
#include "firmware/mapping/LayeredCostmap.hpp"
#include "firmware/mapping/Pose3Tracker.hpp"
#include "firmware/mapping/TerrainAnalysis.hpp"
#include "firmware/mapping/TraversabilityLayer.hpp"

namespace carril::fw {

struct MappingConfig {
  bool enabled = false;  // build a costmap at all (goto needs one; follow_line uses it to avoid)
  CostmapConfig costmap;
  double master_rate_hz = 5.0;  // master rebuilds per second [Hz]
  // The 2D lidar's mount (from the robot's lidar section).
  double lidar_x_m = 0.0, lidar_y_m = 0.0, lidar_yaw_rad = 0.0;
  // Terrain: a 3D lidar is fitted and the traversability layer is built from it.
  bool terrain = false;
  SensorMount lidar3d;
  ElevationConfig elevation;
  TerrainConfig analysis;
  TraversabilityProfile profile;
  double start_free_radius_m = 1.5;  // the blind zone round the start pose, free at start [m]
  int terrain_rows_per_tick =
      4;  // analysed per tick [rows] (a strip costs its rows plus a margin of neighbours)

  Status validate() const;
};

struct MappingTelemetry {
  std::uint32_t scans = 0;           // 2D scans integrated
  std::uint32_t sweeps = 0;          // 3D sweeps fused
  std::uint32_t master_updates = 0;  // master rebuilds
  std::uint32_t skipped_master = 0;  // rebuilds skipped (a layer on another window)
  double z_m = 0.0;                  // the robot's height from the IMU pitch [m]
};

class Mapping final : public CostmapView {
 public:
  // Allocates every grid (init time). cfg must have passed validate().
  Mapping(const MappingConfig& cfg, double tick_rate_hz, const Topic<SensorFrame>& frame,
          const Topic<OdometryMsg>& odom);

  // Task: one tick of mapping work.
  void run();

  const RollingGrid<std::uint8_t>& master() const override { return costmap_.master(); }
  const RollingGrid<std::uint8_t>& obstacles() const override { return costmap_.obstacle_layer(); }
  std::uint32_t updates() const override { return tel_.master_updates; }

  bool enabled() const { return cfg_.enabled; }
  const LayeredCostmap& costmap() const { return costmap_; }
  const ElevationLayer& elevation() const { return elevation_; }
  const TerrainAnalysis& analysis() const { return analysis_; }
  const TraversabilityLayer& traversability() const { return traversability_; }
  const Pose3& pose3() const { return pose3_.pose(); }
  const MappingTelemetry& telemetry() const { return tel_; }
  const MappingConfig& config() const { return cfg_; }

 private:
  MappingConfig cfg_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  LayeredCostmap costmap_;
  ElevationLayer elevation_;
  TerrainAnalysis analysis_;
  TraversabilityLayer traversability_;
  Pose3Tracker pose3_;
  bool started_ = false;
  std::uint32_t master_divisor_ = 1, tick_ = 0;
  std::uint32_t last_scan_seq_ = 0, last_cloud_seq_ = 0;
  // The robot's 3D pose over the last ticks: a sweep is fused with the pose of its stamp (a
  // driver delivers it after the sweep; fusing it with the current pose smears the map).
  struct StampedPose {
    hal::TimeNs t_ns = 0;
    Pose3 pose;
  };
  RingBuffer<StampedPose, 64> history_;
  Pose3 pose_at(hal::TimeNs t_ns) const;
  int next_row_ = 0;  // the analysis' next strip; 0 = waiting for a sweep, -1 = sweep fused
  MappingTelemetry tel_;
};

}  // namespace carril::fw
