#pragma once
// The waypoint mission's test bench: a costmap painted with obstacles (round posts, boxes, walls,
// inflated as the firmware does) and a robot that follows the commanded twist (a unicycle, with
// the firmware's acceleration limits when asked). It records the reaches, the phases, whether the
// centre ever stood on a lethal cell and how close the body's rectangle came to one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "firmware/mission/WaypointMission.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw::test_waypoints {

constexpr double kPostRadius = 0.15;  // [m]

// A window of nx x ny 5 cm cells from (x0, y0) [m]: the master and the lidar layer, written by
// the test.
class CourseCostmap final : public CostmapView {
 public:
  explicit CourseCostmap(double x0 = -2.0, double y0 = -2.0, int nx = 160, int ny = 160) {
    master_.init(nx, ny, 0.05, cost::kFree);
    obstacles_.init(nx, ny, 0.05, cost::kUnknown);
    master_.move_origin(master_.cell_of(x0), master_.cell_of(y0));
    obstacles_.move_origin(obstacles_.cell_of(x0), obstacles_.cell_of(y0));
  }
  const RollingGrid<std::uint8_t>& master() const override { return master_; }
  const RollingGrid<std::uint8_t>& obstacles() const override { return obstacles_; }
  std::uint32_t updates() const override { return updates_; }
  const RollingGrid<std::uint8_t>* walls() const override {
    return walls_.ready() ? &walls_ : nullptr;
  }
  void touch() { ++updates_; }

  // A post that is a wall of the static map: lethal in master and walls(), unseen by the lidar.
  void mapped_post(double px, double py, double r = kPostRadius) {
    if (!walls_.ready()) {
      walls_.init(master_.nx(), master_.ny(), 0.05, cost::kFree);
      walls_.move_origin(master_.origin_cx(), master_.origin_cy());
    }
    post(px, py, false, r);
    for (int cy = walls_.origin_cy(); cy < walls_.origin_cy() + walls_.ny(); ++cy) {
      for (int cx = walls_.origin_cx(); cx < walls_.origin_cx() + walls_.nx(); ++cx) {
        if (std::hypot(walls_.center_of(cx) - px, walls_.center_of(cy) - py) <= r) {
          walls_.at(cx, cy) = cost::kLethal;
        }
      }
    }
  }

  // A round post of radius r at (x, y) [m]. seen_by_lidar: lethal in the lidar layer too.
  void post(double px, double py, bool seen_by_lidar = true, double r = kPostRadius) {
    posts_.push_back(Vec2(px, py));
    paint([=](double x, double y) { return std::hypot(x - px, y - py) - r; }, seen_by_lidar);
  }
  // A box of sx x sy [m] centred at (x, y), turned by yaw [rad].
  void box(double bx, double by, double yaw, double sx, double sy) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    paint(
        [=](double x, double y) {
          const double lx = c * (x - bx) + s * (y - by), ly = -s * (x - bx) + c * (y - by);
          return std::hypot(std::fmax(std::fabs(lx) - 0.5 * sx, 0.0),
                            std::fmax(std::fabs(ly) - 0.5 * sy, 0.0));
        },
        true);
  }
  // Lethal where the shape's distance is 0, inscribed (253) within 0.25 m of it, then
  // 252 exp(-10 (d - 0.25)) out to 0.55 m.
  void paint(const std::function<double(double, double)>& distance, bool seen_by_lidar) {
    for (int cy = master_.origin_cy(); cy < master_.origin_cy() + master_.ny(); ++cy) {
      for (int cx = master_.origin_cx(); cx < master_.origin_cx() + master_.nx(); ++cx) {
        const double d = std::fmax(0.0, distance(master_.center_of(cx), master_.center_of(cy)));
        std::uint8_t& c = master_.at(cx, cy);
        if (d == 0.0) {
          c = cost::kLethal;
          if (seen_by_lidar) obstacles_.at(cx, cy) = cost::kLethal;
        } else if (d <= 0.25 && c != cost::kLethal) {
          c = cost::kInscribed;
        } else if (d <= 0.55 && cost::passable(c)) {
          const auto v = static_cast<std::uint8_t>(252.0 * std::exp(-10.0 * (d - 0.25)));
          if (v > c) c = v;
        }
      }
    }
    ++updates_;
  }
  // Distance from (x, y) to the nearest post's edge [m].
  double clearance(double x, double y) const {
    double best = 1e9;
    for (const Vec2& p : posts_) best = std::fmin(best, std::hypot(x - p.x(), y - p.y()));
    return best - kPostRadius;
  }
  // From the body's rectangle at pose to the nearest lethal cell, the cell a 5 cm square [m]; 0
  // when they overlap.
  double body_clearance(const Pose2& pose, const Footprint& fp) const {
    const double reach = std::hypot(fp.half_length_m, fp.half_width_m) + 0.6;
    const int x0 = master_.cell_of(pose.x - reach), x1 = master_.cell_of(pose.x + reach);
    const int y0 = master_.cell_of(pose.y - reach), y1 = master_.cell_of(pose.y + reach);
    const double half = 0.5 * master_.resolution();
    double best = 0.6;
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        if (!master_.contains(cx, cy) || master_.at(cx, cy) != cost::kLethal) continue;
        const Vec2 p = to_robot(pose, Vec2(master_.center_of(cx), master_.center_of(cy)));
        // Cell square against the rectangle (the cell's axes are the world's; bounded by its
        // circumscribed circle, a slight under-estimate of the gap).
        const double dx = std::fmax(std::fabs(p.x()) - fp.half_length_m, 0.0);
        const double dy = std::fmax(std::fabs(p.y()) - fp.half_width_m, 0.0);
        best = std::fmin(best, std::fmax(0.0, std::hypot(dx, dy) - half * std::sqrt(2.0)));
      }
    }
    return best;
  }

 private:
  RollingGrid<std::uint8_t> master_, obstacles_, walls_;
  std::vector<Vec2> posts_;
  std::uint32_t updates_ = 0;
};

// A mission on a costmap with a robot that follows its twist.
struct Bench {
  explicit Bench(CourseCostmap* map = nullptr) : costmap(map != nullptr ? *map : own) {}

  WaypointConfig cfg;
  Footprint footprint{0.25, 0.25};
  Topic<OdometryMsg> odom;
  CourseCostmap own;
  CourseCostmap& costmap;
  Topic<CostmapMsg> costmap_topic{CostmapMsg{&costmap}};  // the bus's costmap topic
  std::unique_ptr<WaypointMission> mission;
  Pose2 pose{0.0, 0.0, 0.0};
  int tick = 0;
  bool drives_ready = true;
  // The robot's own limits, as the firmware's MotionLimiter applies them (0: none).
  double max_accel_mps2 = 0.0, max_yaw_accel_radps2 = 0.0;
  Twist moving;                     // the twist the robot drives at
  double turned_rad = 0.0;          // all the turning, either way [rad]
  bool on_lethal = false;           // the centre on a lethal cell
  double min_clearance = 1e9;       // centre to the nearest post's edge [m]
  double min_body_clearance = 1e9;  // body's rectangle to the nearest lethal cell [m]
  std::vector<std::size_t> order;   // the target index at every reach
  std::vector<double> reach_miss;   // distance to the reached target then [m]
  std::vector<std::string> phases;  // every phase change reported
  std::vector<double> phase_dist;   // the distance to the current target at each [m]
  bool allocations_counted = false;

  void start() {
    mission = std::make_unique<WaypointMission>(cfg, footprint, false, odom, costmap_topic);
    mission->enter(MissionContext{});
  }
  double t_s() const { return tick * 0.01; }
  // Runs until done or failed or `seconds` pass; the robot follows the twist (unicycle).
  MissionOutput run(double seconds) {
    MissionOutput out;
    for (int i = 0; i < int(seconds * 100); ++i, ++tick) {
      odom.publish(OdometryMsg{pose, {}}, tick);
      MissionContext ctx;
      ctx.t_s = t_s();
      ctx.dt_s = 0.01;
      ctx.drives_ready = drives_ready;
      const std::uint32_t before = mission->targets_reached();
      const std::size_t target = mission->target_index();
      if (allocations_counted) alloc::begin_window();
      out = mission->update(ctx);
      if (allocations_counted) alloc::end_window();
      if (const char* p = mission->take_phase_change()) {
        phases.push_back(p);
        const std::size_t k = std::min(mission->target_index(), cfg.targets.size() - 1);
        phase_dist.push_back((cfg.targets[k] - Vec2(pose.x, pose.y)).norm());
      }
      if (mission->targets_reached() != before) {
        order.push_back(target);
        reach_miss.push_back((cfg.targets[target] - Vec2(pose.x, pose.y)).norm());
      }
      const MissionStatus s = mission->state().status;
      if (s == MissionStatus::Done || s == MissionStatus::Failed) break;
      follow(out.motion.twist);
      int cx = 0, cy = 0;
      if (costmap.master().world_to_cell(pose.x, pose.y, cx, cy) &&
          costmap.master().at(cx, cy) == cost::kLethal) {
        on_lethal = true;
      }
      min_clearance = std::fmin(min_clearance, costmap.clearance(pose.x, pose.y));
      min_body_clearance = std::fmin(min_body_clearance, costmap.body_clearance(pose, footprint));
    }
    return out;
  }
  void follow(const Twist& want) {
    Twist t = want;
    if (max_accel_mps2 > 0.0) {
      const double dv = max_accel_mps2 * 0.01, dw = max_yaw_accel_radps2 * 0.01;
      t.vx = clampd(t.vx, moving.vx - dv, moving.vx + dv);
      t.wz = clampd(t.wz, moving.wz - dw, moving.wz + dw);
    }
    moving = t;
    turned_rad += std::fabs(t.wz) * 0.01;
    pose.x += std::cos(pose.yaw) * t.vx * 0.01;
    pose.y += std::sin(pose.yaw) * t.vx * 0.01;
    pose.yaw = wrap_angle(pose.yaw + t.wz * 0.01);
  }
};

inline std::uint32_t counter(const WaypointMission& m, const char* name) {
  MissionCounters c;
  m.counters(c);
  for (const MissionCounter& k : c)
    if (std::strcmp(k.name, name) == 0) return k.value;
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

}  // namespace carril::fw::test_waypoints
