#include "firmware/mapping/Mapping.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

Status MappingConfig::validate() const {
  Checks c("mapping");
  if (!enabled) return c.result();
  c.nested(costmap.validate())
      .range("master_rate_hz", master_rate_hz, 0.1, 100.0, "Hz")
      .range("start_free_radius_m", start_free_radius_m, 0.0, 10.0, "m")
      .range("terrain_rows_per_tick", double(terrain_rows_per_tick), 1.0, 10000.0, "rows")
      .range("fuse_points_per_tick", double(fuse_points_per_tick), 100.0, 1e7, "points")
      .range("fuse_cells_per_tick", double(fuse_cells_per_tick), 100.0, 1e7, "cells");
  if (terrain) {
    c.nested(elevation.validate()).nested(analysis.validate()).nested(profile.validate());
    c.fail_if(std::fabs(elevation.size_x_m - costmap.size_x_m) > 1e-9 ||
                  std::fabs(elevation.size_y_m - costmap.size_y_m) > 1e-9 ||
                  std::fabs(elevation.resolution_m - costmap.resolution_m) > 1e-12,
              "elevation",
              "must have the costmap's window and resolution (layers combine cell by cell)");
  }
  return c.result();
}

CostmapConfig costmap_for_map(const CostmapConfig& cfg, const MapInfo& map) {
  CostmapConfig c = cfg;
  c.resolution_m = map.resolution_m;
  c.size_x_m = (map.nx + 2) * map.resolution_m;
  c.size_y_m = (map.ny + 2) * map.resolution_m;
  return c;
}

// The pose at the tick nearest t_ns (the newest when t_ns is newer, the oldest kept when older).
Pose3 Mapping::pose_at(hal::TimeNs t_ns) const {
  Pose3 best = pose3_.pose();
  hal::TimeNs best_dt = -1;
  for (std::size_t i = 0; i < history_.size(); ++i) {
    const hal::TimeNs dt =
        history_[i].t_ns > t_ns ? history_[i].t_ns - t_ns : t_ns - history_[i].t_ns;
    if (best_dt < 0 || dt < best_dt) {
      best_dt = dt;
      best = history_[i].pose;
    }
  }
  return best;
}

Mapping::Mapping(const MappingConfig& cfg, double tick_rate_hz, const Pose2& lidar_mount,
                 const Topic<SensorFrame>& frame, const Topic<OdometryMsg>& pose,
                 const OccupancyGrid* static_map, Topic<CostmapMsg>* costmap)
    : cfg_(cfg), lidar_mount_(lidar_mount), frame_(frame), odom_(pose) {
  if (!cfg_.enabled) return;
  // The view is this object: it reads "no master yet" (updates() 0) until the first rebuild.
  if (costmap != nullptr) costmap->publish(CostmapMsg{this}, 0);
  if (static_map != nullptr && !static_map->empty()) {
    static_map_ = static_map;
    cfg_.costmap = costmap_for_map(cfg_.costmap, static_map->info());
    cfg_.terrain = false;
  }
  // Init failures are configuration errors validate() should have rejected: kept in init_status()
  // (the wiring refuses to start), and run() does nothing.
  if (!take(costmap_.init(cfg_.costmap))) return;
  master_divisor_ = std::max<std::uint32_t>(
      1, static_cast<std::uint32_t>(std::lround(tick_rate_hz / cfg_.master_rate_hz)));
  if (cfg_.terrain) {
    if (!take(elevation_.init(cfg_.elevation)) ||
        !take(analysis_.init(cfg_.analysis, cfg_.costmap.nx(), cfg_.costmap.ny(),
                             cfg_.costmap.resolution_m)) ||
        !take(traversability_.init(cfg_.costmap.nx(), cfg_.costmap.ny(),
                                   cfg_.costmap.resolution_m))) {
      return;
    }
  }
  if (static_map_ != nullptr) {
    // One window over the whole map, placed once.
    const MapInfo& m = static_map_->info();
    const double cx = m.origin_x_m + 0.5 * m.nx * m.resolution_m;
    const double cy = m.origin_y_m + 0.5 * m.ny * m.resolution_m;
    if (Status s =
            static_layer_.init(cfg_.costmap.nx(), cfg_.costmap.ny(), cfg_.costmap.resolution_m);
        !s) {
      take(s);
      return;
    }
    static_layer_.place(*static_map_, cx, cy);
    costmap_.recenter(cx, cy);
    const RollingGrid<std::uint8_t>* layers[] = {&static_layer_.grid()};
    costmap_.update_master(layers, 1);
    return;
  }
  // Place the windows round the odometry origin (the start pose) now, at init: the first tick
  // then moves them by the start pose's few cells at most, instead of laying out every cell.
  costmap_.recenter(0.0, 0.0);
  if (cfg_.terrain) {
    elevation_.recenter(0.0, 0.0);
    traversability_.move_window(elevation_.grid().origin_cx(), elevation_.grid().origin_cy());
  }
}

bool Mapping::take(const Status& s) {
  if (!s && init_) init_ = s;
  return static_cast<bool>(s);
}

void Mapping::run() {
  if (!cfg_.enabled || !init_) return;
  const SensorFrame& f = frame_.get();
  const Pose2 pose = odom_.get().pose;
  if (!started_) {
    pose3_.reset(pose);
    if (static_map_ == nullptr) costmap_.recenter(pose.x, pose.y);
    if (cfg_.terrain) {
      elevation_.recenter(pose.x, pose.y);
      traversability_.mark_start_free(pose.x, pose.y, cfg_.start_free_radius_m);
    }
    started_ = true;
  }
  if (f.imu.valid) {
    pose3_.update(pose, f.imu.roll_rad, f.imu.pitch_rad);
  } else {
    pose3_.update(pose, 0.0F, 0.0F);
  }
  tel_.z_m = pose3_.pose().z;
  history_.push({f.now_ns, pose3_.pose()});
  ++tick_;

  if (!cfg_.terrain && static_map_ == nullptr) {
    // Obstacles only: the window follows the robot every tick (moving costs only the cells that
    // enter), the master is rebuilt at master_rate_hz.
    costmap_.recenter(pose.x, pose.y);
  }
  const OdometryMsg& pm = odom_.get();
  bool cleared = false;
  if (pm.relocalisations != seen_relocalisations_) {
    seen_relocalisations_ = pm.relocalisations;
    costmap_.obstacles().clear();
    ++tel_.obstacle_clears;
    cleared = true;
  }
  bool scanned = false;
  const hal::LaserScan* scan = scans_.take(f.scan);
  if (scan != nullptr && !pm.localised) {
    ++tel_.scans_unlocalised;
  } else if (scan != nullptr) {
    const Vec2 s = to_world(pose, Vec2(lidar_mount_.x, lidar_mount_.y));
    costmap_.update_obstacles(*scan, Pose2{s.x(), s.y(), wrap_angle(pose.yaw + lidar_mount_.yaw)});
    ++tel_.scans;
    scanned = true;
  }
  if (!cfg_.terrain) {
    // A clearing reaches the master at once: a mission replanning on the jump reads it next.
    if (cleared || tick_ % master_divisor_ == 0) {
      if (static_map_ != nullptr) {
        const RollingGrid<std::uint8_t>* layers[] = {&static_layer_.grid()};
        costmap_.update_master(layers, 1);
      } else {
        costmap_.update_master();
      }
      ++tel_.master_updates;
    }
    return;
  }
  // One bounded piece per tick: a scan, or else a master rebuild when one is due (obstacles reach
  // the missions at master_rate_hz, the terrain as its cycle completes), or else a terrain piece.
  // Not before the first terrain cycle is complete: a master without any terrain would let a
  // mission plan over ground nobody has judged.
  if (tel_.master_updates > 0 && tick_ % master_divisor_ == 0) master_due_ = true;
  if (scanned) return;
  if (master_due_) {
    rebuild_master();
    return;
  }
  terrain_piece(f);
}

void Mapping::rebuild_master() {
  master_due_ = false;
  const RollingGrid<std::uint8_t>* layers[] = {&traversability_.grid()};
  if (costmap_.update_master(layers, 1)) {
    ++tel_.master_updates;
  } else {
    ++tel_.skipped_master;
  }
}

void Mapping::begin_sweep(const hal::PointCloud& cloud, const Pose2& pose) {
  clouds_.take(&cloud);
  binning_seq_ = cloud.seq;
  // The windows move only between cycles, so every piece of a cycle lands on one window.
  costmap_.recenter(pose.x, pose.y);
  elevation_.recenter(pose.x, pose.y);
  traversability_.move_window(elevation_.grid().origin_cx(), elevation_.grid().origin_cy());
  const Pose3 p = pose_at(cloud.stamp_ns);
  next_point_ = 0;
  phase_ = elevation_.begin_sweep(std::int64_t(cloud.stamp_ns), sensor_pose_of(p, cfg_.lidar3d))
               ? TerrainPhase::kBin
               : TerrainPhase::kWaitSweep;
}

void Mapping::terrain_piece(const SensorFrame& f) {
  const bool fresh = clouds_.fresh(f.cloud);
  switch (phase_) {
    case TerrainPhase::kWaitSweep:
      if (fresh) begin_sweep(*f.cloud, odom_.get().pose);
      return;
    case TerrainPhase::kBin: {
      // The sweep being binned is replaced once a newer one is out (the driver may reuse its
      // buffer): start over with the newest; nothing of the old one reached the map.
      if (f.cloud == nullptr || f.cloud->seq != binning_seq_) {
        ++tel_.sweeps_abandoned;
        phase_ = TerrainPhase::kWaitSweep;
        if (f.cloud != nullptr) begin_sweep(*f.cloud, odom_.get().pose);
        return;
      }
      const std::uint32_t n = std::uint32_t(cfg_.fuse_points_per_tick);
      elevation_.bin_points(*f.cloud, next_point_, n);
      next_point_ += n;
      if (next_point_ >= f.cloud->count) phase_ = TerrainPhase::kFuse;
      return;
    }
    case TerrainPhase::kFuse:
      if (!elevation_.fuse_step(std::uint32_t(cfg_.fuse_cells_per_tick))) return;
      ++tel_.sweeps;
      next_row_ = 0;
      phase_ = TerrainPhase::kAnalyse;
      return;
    case TerrainPhase::kAnalyse: {
      const int ny = elevation_.grid().ny();
      const int rows = std::min(cfg_.terrain_rows_per_tick, ny - next_row_);
      analysis_.compute(elevation_.grid(), 0, next_row_, elevation_.grid().nx(), rows);
      traversability_.update(analysis_, cfg_.profile);
      next_row_ += rows;
      if (next_row_ >= ny) phase_ = TerrainPhase::kMaster;
      return;
    }
    case TerrainPhase::kMaster:
      rebuild_master();
      phase_ = TerrainPhase::kWaitSweep;
      return;
  }
}

}  // namespace carril::fw
