// CoverageMission on a hand-made two-room map with a door, driven in a kinematic loop: the robot
// moves exactly as commanded (a unicycle at 100 Hz) and its pose is fed back as the localised
// pose; the costmap is the static map's walls inflated as the firmware does, plus, in one case,
// an obstacle the static map does not show, revealed when the robot comes within lidar range.
#include "firmware/mission/CoverageMission.hpp"
#include "firmware/mission/SystematicCoverage.hpp"
#include "firmware/mission/VacuumCoverage.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

constexpr double kRes = 0.05;
constexpr int kNx = 124, kNy = 72;  // 6.2 x 3.6 m

struct Box {
  double x0, y0, x1, y1;  // [m]
};

// Two rooms, 0.1 m walls, a 0.9 m door in the wall between them.
std::vector<std::uint8_t> two_rooms(const std::vector<Box>& extra = {}) {
  std::vector<std::uint8_t> c(std::size_t(kNx * kNy), cost::kFree);
  for (int j = 0; j < kNy; ++j) {
    for (int i = 0; i < kNx; ++i) {
      const double x = (i + 0.5) * kRes, y = (j + 0.5) * kRes;
      bool wall = x < 0.1 || y < 0.1 || x > 6.1 || y > 3.5;
      wall = wall || (x > 3.0 && x < 3.1 && !(y > 1.4 && y < 2.3));
      for (const Box& b : extra) wall = wall || (x > b.x0 && x < b.x1 && y > b.y0 && y < b.y1);
      if (wall) c[std::size_t(j * kNx + i)] = cost::kLethal;
    }
  }
  return c;
}

MapInfo map_info() {
  MapInfo info;
  info.nx = kNx;
  info.ny = kNy;
  info.resolution_m = kRes;
  return info;
}

// The master costmap: the lethal cells of a map inflated as the firmware does (inscribed within
// 0.25 m, then 252 exp(-10 (d - 0.25)) out to 0.55 m).
class TestCostmap final : public CostmapView {
 public:
  TestCostmap() {
    master_.init(kNx + 6, kNy + 6, kRes, cost::kFree);
    obstacles_.init(kNx + 6, kNy + 6, kRes, cost::kUnknown);
    master_.move_origin(-3, -3);
    obstacles_.move_origin(-3, -3);
  }
  const RollingGrid<std::uint8_t>& master() const override { return master_; }
  const RollingGrid<std::uint8_t>& obstacles() const override { return obstacles_; }
  std::uint32_t updates() const override { return updates_; }
  void build(const std::vector<std::uint8_t>& cells) {
    master_.clear();
    constexpr int r = 11;
    for (int j = 0; j < kNy; ++j) {
      for (int i = 0; i < kNx; ++i) {
        if (cells[std::size_t(j * kNx + i)] != cost::kLethal) continue;
        for (int dj = -r; dj <= r; ++dj) {
          for (int di = -r; di <= r; ++di) {
            if (!master_.contains(i + di, j + dj)) continue;
            std::uint8_t& m = master_.at(i + di, j + dj);
            const double d = std::hypot(di, dj) * kRes;
            std::uint8_t c = 0;
            if (d == 0.0) {
              c = cost::kLethal;
            } else if (d <= 0.25 + 1e-9) {
              c = cost::kInscribed;
            } else if (d <= 0.55) {
              c = static_cast<std::uint8_t>(252.0 * std::exp(-10.0 * (d - 0.25)));
            }
            if (c > m) m = c;
          }
        }
      }
    }
    ++updates_;
  }

 private:
  RollingGrid<std::uint8_t> master_, obstacles_;
  std::uint32_t updates_ = 0;
};

struct Result {
  double time_s = 0.0;
  double path_m = 0.0;
  int collisions = 0;           // ticks with a wall or obstacle cell under the body's circle
  double min_obstacle_m = 1e9;  // robot centre to the hidden obstacle
  bool backed_up_after_bump = false, turned_after_backup = false;
  // Fastest speed in TRANSIT with a wall cell within 0.33 m of the centre, and farther [m/s].
  double transit_vx_near_wall = 0.0, transit_vx_open = 0.0;
  // Where sweeps start: the farthest the robot stood from the route's first point when that
  // lay ahead of it along the route, and how many routes were made to start where it stood [m,
  // sweeps].
  double sweep_start_off_m = 0.0;
  int sweeps_from_the_robot = 0, sweeps = 0;
  double tour_s = -1.0;  // when the tour of the cells ended (the first revisit plan, or done) [s]
  std::vector<double> update_us;  // update() times on this host (figures, not tests) [us]
  double update_percentile(double q) const {
    if (update_us.empty()) return 0.0;
    std::vector<double> v = update_us;
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
  }
};

struct Rig {
  // `walls`: more walls on the map (and in the world); `hidden`: obstacles the map does not show.
  explicit Rig(CoverageMode mode, std::vector<Box> hidden = {}, std::vector<Box> walls = {})
      : hidden_(std::move(hidden)) {
    cfg.mode = mode;
    static_cells = two_rooms(walls);
    EXPECT_TRUE(map.assign(map_info(), static_cells.data()).is_ok());
    walls.insert(walls.end(), hidden_.begin(), hidden_.end());
    truth = two_rooms(walls);
    costmap.build(static_cells);
  }
  CoverageConfig cfg;
  std::vector<std::uint8_t> static_cells, truth;
  OccupancyGrid map{std::size_t(kNx * kNy)};
  Topic<OdometryMsg> pose_topic;
  TestCostmap costmap;
  Topic<CostmapMsg> costmap_topic{CostmapMsg{&costmap}};  // the bus's costmap topic
  std::unique_ptr<CoverageMission> mission;
  MissionContext ctx;
  Pose2 pose{0.6, 0.6, 0.0};
  bool revealed = false;
  bool count_allocations = false;
  std::vector<Box> hidden_;
  bool trace_ = std::getenv("COVERAGE_TRACE") != nullptr;

  // The systematic mission (mode: systematic, the Rig's default).
  const SystematicCoverage& systematic() const {
    return static_cast<const SystematicCoverage&>(*mission);
  }
  void start() {
    mission =
        make_coverage_mission(cfg, Footprint{0.25, 0.25}, false, pose_topic, costmap_topic, map);
    mission->enter(ctx);
    if (trace_ && cfg.mode == CoverageMode::Systematic) {
      const Boustrophedon& b = systematic().decomposition();
      for (std::size_t k = 0; k < b.cell_count(); ++k) {
        const CoverCell& c = b.cell(k);
        std::printf("  cell %zu: columns %d..%d, %u lanes, %u cells\n", k, c.x0, c.x1, c.lanes,
                    c.area);
      }
    }
  }
  // True when a lethal cell of the true world lies within the body's inscribed circle (less
  // half a cell of discretisation).
  bool collides() const {
    const int r = 5;
    const int ci = int(std::floor(pose.x / kRes)), cj = int(std::floor(pose.y / kRes));
    for (int dj = -r; dj <= r; ++dj) {
      for (int di = -r; di <= r; ++di) {
        const int i = ci + di, j = cj + dj;
        if (i < 0 || j < 0 || i >= kNx || j >= kNy) continue;
        if (truth[std::size_t(j * kNx + i)] != cost::kLethal) continue;
        const double d = std::hypot((i + 0.5) * kRes - pose.x, (j + 0.5) * kRes - pose.y);
        if (d < 0.25 - 0.5 * kRes) return true;
      }
    }
    return false;
  }
  // Distance from the centre to the nearest lethal cell's centre of the true world within 0.5 m
  // (0.5 m when none) [m].
  double wall_distance() const {
    const int r = 10;
    const int ci = int(std::floor(pose.x / kRes)), cj = int(std::floor(pose.y / kRes));
    double best = 0.5;
    for (int dj = -r; dj <= r; ++dj) {
      for (int di = -r; di <= r; ++di) {
        const int i = ci + di, j = cj + dj;
        if (i < 0 || j < 0 || i >= kNx || j >= kNy) continue;
        if (truth[std::size_t(j * kNx + i)] != cost::kLethal) continue;
        best = std::fmin(best, std::hypot((i + 0.5) * kRes - pose.x, (j + 0.5) * kRes - pose.y));
      }
    }
    return best;
  }
  // Runs until the mission is done or failed or `seconds` pass.
  Result run(double seconds) {
    Result r;
    CoverageMission::State prev = mission->current();
    const int ticks = int(seconds * 100);
    for (int k = 0; k < ticks; ++k) {
      pose_topic.publish(OdometryMsg{pose, {}}, k);
      ctx.t_s = k * 0.01;
      ctx.dt_s = 0.01;
      ctx.drives_ready = true;
      if (count_allocations) alloc::begin_window();
      const auto t0 = std::chrono::steady_clock::now();
      const MissionOutput out = mission->update(ctx);
      const double us =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
      if (count_allocations) alloc::end_window();
      r.update_us.push_back(us);
      const CoverageMission::State now = mission->current();
      if (prev == CoverageMission::State::Forward || prev == CoverageMission::State::Spiral) {
        if (now == CoverageMission::State::BackUp) r.backed_up_after_bump = true;
      }
      if (prev == CoverageMission::State::BackUp && now == CoverageMission::State::Turn) {
        r.turned_after_backup = true;
      }
      if (now == CoverageMission::State::Sweep && prev != CoverageMission::State::Sweep) {
        std::size_t n = 0;
        const Vec2* route = systematic().sweep_route(n);
        const Vec2 to = n > 0 ? route[0] - Vec2(pose.x, pose.y) : Vec2(0.0, 0.0);
        const double off = to.norm();
        // A robot already past the route's start along it converges onto the lane ahead.
        const bool ahead =
            n < 2 || to.dot(route[1] - route[0]) >= -0.5 * off * (route[1] - route[0]).norm();
        if (ahead) r.sweep_start_off_m = std::fmax(r.sweep_start_off_m, off);
        if (off == 0.0) ++r.sweeps_from_the_robot;
        ++r.sweeps;
      }
      prev = now;
      const char* ph = mission->take_phase_change();
      if (ph != nullptr && r.tour_s < 0.0 &&
          (std::strcmp(ph, "revisit") == 0 || std::strcmp(ph, "done") == 0)) {
        r.tour_s = ctx.t_s;
      }
      if (ph != nullptr && trace_) {
        std::printf("  %7.2f s %-8s %-10s (%.2f, %.2f, %.2f)\n", ctx.t_s, mission->state().name, ph,
                    pose.x, pose.y, pose.yaw);
      }
      const MissionStatus s = mission->state().status;
      if (s == MissionStatus::Done || s == MissionStatus::Failed) break;
      const Twist& t = out.motion.twist;
      if (now == CoverageMission::State::Transit) {
        double& v = wall_distance() < 0.33 ? r.transit_vx_near_wall : r.transit_vx_open;
        v = std::fmax(v, t.vx);
      }
      pose.x += std::cos(pose.yaw) * t.vx * 0.01;
      pose.y += std::sin(pose.yaw) * t.vx * 0.01;
      pose.yaw = wrap_angle(pose.yaw + t.wz * 0.01);
      r.path_m += std::fabs(t.vx) * 0.01;
      r.time_s = (k + 1) * 0.01;
      if (collides()) {
        ++r.collisions;
        if (trace_)
          std::printf("  collision %.2f s %s (%.3f, %.3f, %.2f) v %.2f w %.2f\n", ctx.t_s,
                      mission->state().phase, pose.x, pose.y, pose.yaw, t.vx, t.wz);
      }
      for (const Box& b : hidden_) {
        const double dx = std::fmax(0.0, std::fmax(b.x0 - pose.x, pose.x - b.x1));
        const double dy = std::fmax(0.0, std::fmax(b.y0 - pose.y, pose.y - b.y1));
        const double d = std::hypot(dx, dy);
        r.min_obstacle_m = std::fmin(r.min_obstacle_m, d);
        // The lidar sees it from 1.5 m: from then on the costmap shows it.
        if (!revealed && d < 1.5) {
          revealed = true;
          costmap.build(truth);
        }
      }
    }
    return r;
  }
};

// The reachable coverable cells of the true world (the hidden obstacle included) from the start.
std::vector<std::uint8_t> reachable_truth(const Rig& rig) {
  OccupancyGrid world(std::size_t(kNx * kNy));
  EXPECT_TRUE(world.assign(map_info(), rig.truth.data()).is_ok());
  CoverageArea area(std::size_t(kNx * kNy));
  CoverageAreaConfig ac;
  ac.tool_width_m = rig.cfg.tool_width_m;
  EXPECT_TRUE(area.build(world, ac).is_ok());
  EXPECT_TRUE(area.keep_component(int(0.6 / kRes), int(0.6 / kRes)));
  return std::vector<std::uint8_t>(area.coverable(), area.coverable() + area.size());
}

double covered_of(const CoverageMission& m, const std::vector<std::uint8_t>& mask,
                  std::size_t* cells = nullptr) {
  std::size_t n = 0, covered = 0;
  for (std::size_t k = 0; k < mask.size(); ++k) {
    if (mask[k] == 0) continue;
    ++n;
    if (m.coverage().counts()[k] > 0) ++covered;
  }
  if (cells != nullptr) *cells = n;
  return double(covered) / double(n);
}

// free area / (tool width x cruise speed) [s]
double lower_bound_s(std::size_t cells, const CoverageConfig& cfg) {
  return double(cells) * kRes * kRes / (cfg.tool_width_m * cfg.speed_mps);
}

void report(const char* what, const Rig& rig, const Result& r, double covered, double lb) {
  MissionCounters c;
  rig.mission->counters(c);
  std::printf(
      "%s: %s, covered %.1f %% in %.1f s (lower bound %.1f s, %.2fx), path %.1f m, "
      "overlap %.1f %%, collisions %d, update p99.9 %.0f us (max %.0f us, preemption incl.);",
      what, rig.mission->state().name, 100.0 * covered, r.time_s, lb, r.time_s / lb, r.path_m,
      100.0 * rig.mission->coverage().overlap_fraction(), r.collisions, r.update_percentile(0.999),
      r.update_percentile(1.0));
  for (const MissionCounter& k : c) std::printf(" %s %u", k.name, k.value);
  std::printf("\n");
}

// The covered fraction of the true reachable area; prints it with the run's figures.
double covered_and_report(const char* what, const Rig& rig, const Result& r) {
  std::size_t cells = 0;
  const double covered = covered_of(*rig.mission, reachable_truth(rig), &cells);
  report(what, rig, r, covered, lower_bound_s(cells, rig.cfg));
  return covered;
}

TEST(CoverageMissionTest, SystematicCoversTheTwoRoomsAndEndsDone) {
  Rig rig(CoverageMode::Systematic);
  rig.start();
  ASSERT_TRUE(rig.mission->init_status().is_ok()) << rig.mission->init_status().message();
  const Result r = rig.run(600.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  const double covered = covered_and_report("systematic", rig, r);
  EXPECT_GE(covered, 0.95);
  EXPECT_EQ(r.collisions, 0);
  MissionCounters c;
  rig.mission->counters(c);
  EXPECT_GE(c[0].value, 3u);  // cells: both rooms and the door at least
  EXPECT_EQ(c[2].value, 0u);  // no lane blocked
}

// Transits above the lanes' speed only in the open: within 0.33 m of a wall cell (the body's 0.25 m
// radius, the 0.1 m edge margin less a cell's diagonal) at the lanes' speed at most.
// A new cell's sweep starts on its route: where the robot stands 3 cm or more short of or beside
// the route's first point (a cell that begins just beside where the last one ended is not driven
// to by a transit), the route is made to start where it stands, and the robot drives onto the
// lane before along it, instead of converging onto the lane along a first stretch run wide of it.
// (Past the first point along the route, it converges onto the lane ahead: going back would be a
// turn about.)
TEST(CoverageMissionTest, ANewCellsSweepStartsWhereTheRobotStands) {
  Rig rig(CoverageMode::Systematic);
  rig.start();
  const Result r = rig.run(600.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  std::printf("%d sweeps, %d started where the robot stood, the farthest start %.3f m off\n",
              r.sweeps, r.sweeps_from_the_robot, r.sweep_start_off_m);
  EXPECT_LT(r.sweep_start_off_m, 0.03);
  EXPECT_GE(r.sweeps_from_the_robot, 1);  // the case happens in these rooms
  EXPECT_EQ(r.collisions, 0);
}

// A step in the left room's top wall splits it into cells whose lanes meet across the cells'
// border at the bottom: the sweep turns from the last lane of one into the first of the next by a
// U-turn, as between its own lanes, instead of a plan, a transit and two turns on the spot;
// faster, as covered, and clear of the walls.
TEST(CoverageMissionTest, ACellBesideTheLastLaneIsJoinedByAUTurn) {
  // The top wall 0.5 m lower from x = 1.5 m to the wall between the rooms.
  const std::vector<Box> top_step = {Box{1.5, 3.0, 3.0, 3.6}};
  double time_s[2] = {0.0, 0.0}, covered[2] = {0.0, 0.0};  // the tour's time [s]
  std::uint32_t joins[2] = {0, 0};
  for (int with = 0; with < 2; ++with) {
    Rig rig(CoverageMode::Systematic, {}, top_step);
    rig.cfg.join_max_gap_m = with != 0 ? 1.0 : 0.0;
    rig.start();
    ASSERT_TRUE(rig.mission->init_status().is_ok()) << rig.mission->init_status().message();
    const Result r = rig.run(900.0);
    ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
    covered[with] = covered_and_report(with != 0 ? "joined" : "not joined", rig, r);
    time_s[with] = r.tour_s;
    joins[with] = rig.mission->joins();
    EXPECT_EQ(r.collisions, 0);
  }
  EXPECT_EQ(joins[0], 0u);
  EXPECT_GE(joins[1], 1u);
  EXPECT_LT(time_s[1], time_s[0]);
  EXPECT_GE(covered[1], covered[0] - 0.01);
  EXPECT_GE(covered[1], 0.95);
}

// After the tour, a revisit goes only for a patch of unswept cells of at least
// revisit_min_area_m2: the scallops of a few cells the lanes leave by the walls are not worth a
// plan, a transit and a turn on the spot each. Fewer revisits, sooner done, as covered within a
// point.
TEST(CoverageMissionTest, RevisitsGoOnlyForPatchesWorthTheTrip) {
  double time_s[2] = {0.0, 0.0}, covered[2] = {0.0, 0.0};
  std::uint32_t revisits[2] = {0, 0};
  for (int small = 0; small < 2; ++small) {
    Rig rig(CoverageMode::Systematic);
    rig.cfg.revisit_min_area_m2 = small != 0 ? 0.0 : 0.05;
    rig.start();
    const Result r = rig.run(900.0);
    ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
    covered[small] = covered_and_report(small != 0 ? "any patch" : "0.05 m^2 or more", rig, r);
    time_s[small] = r.time_s;
    MissionCounters c;
    rig.mission->counters(c);
    revisits[small] = c[3].value;
    EXPECT_EQ(r.collisions, 0);
  }
  EXPECT_GT(revisits[1], revisits[0]);
  EXPECT_LT(time_s[0], time_s[1]);
  EXPECT_GE(covered[0], covered[1] - 0.01);
  EXPECT_GE(covered[0], 0.95);
}

TEST(CoverageMissionTest, TransitsAreFastInTheOpenAndSlowNearWalls) {
  Rig rig(CoverageMode::Systematic);
  rig.cfg.transit_speed_mps = 0.8;
  rig.cfg.transit_pursuit.cruise_speed_mps = 0.8;
  rig.start();
  ASSERT_TRUE(rig.mission->init_status().is_ok()) << rig.mission->init_status().message();
  const Result r = rig.run(600.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  EXPECT_GT(r.transit_vx_open, rig.cfg.speed_mps + 0.1);
  EXPECT_GT(r.transit_vx_near_wall, 0.0);
  EXPECT_LE(r.transit_vx_near_wall, rig.cfg.speed_mps + 1e-9);
  EXPECT_EQ(r.collisions, 0);
}

TEST(CoverageMissionTest, AnObstacleMissingFromTheMapIsDrivenRoundAndItsSurroundsSwept) {
  Rig rig(CoverageMode::Systematic, {Box{1.4, 1.2, 1.8, 1.7}});
  rig.start();
  const Result r = rig.run(900.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  const double covered = covered_and_report("systematic, unmapped obstacle", rig, r);
  EXPECT_GE(covered, 0.95);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_GT(r.min_obstacle_m, 0.25 - 0.5 * kRes);  // the body never reached it
  std::printf("closest approach of the centre to the obstacle: %.3f m\n", r.min_obstacle_m);
  MissionCounters c;
  rig.mission->counters(c);
  EXPECT_GE(c[2].value, 1u);  // lanes_blocked
}

// The clearance kept from the walls is kept from an obstacle the map does not show too: its plan
// cost disk and the lane cut both reach the inscribed radius plus wall_clearance_m (with the
// radius alone, transits passed 1 cm from such obstacles in the house and touched them).
TEST(CoverageMissionTest, AnUnmappedObstacleIsKeptAtTheWallClearance) {
  Rig rig(CoverageMode::Systematic, {Box{1.4, 1.2, 1.8, 1.7}});
  rig.cfg.wall_clearance_m = 0.1;
  rig.start();
  const Result r = rig.run(900.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  covered_and_report("systematic, unmapped obstacle, 0.1 m clearance", rig, r);
  EXPECT_EQ(r.collisions, 0);
  // The centre stays the radius and the clearance away, less a cell (the grid's rounding).
  EXPECT_GT(r.min_obstacle_m, 0.25 + 0.1 - kRes);
  std::printf("closest approach of the centre to the obstacle: %.3f m\n", r.min_obstacle_m);
  MissionCounters c;
  rig.mission->counters(c);
  EXPECT_GE(c[2].value, 1u);  // lanes_blocked
}

// Lidar returns off a wall's face land in the free cell before it about half the time: a costmap
// whose walls are a cell thicker than the map's. Those are the walls the area already keeps
// clear of, not obstacles: the lanes along them are swept, none is cut.
TEST(CoverageMissionTest, LethalCellsOnAWallsFaceAreTheWallNotAnObstacle) {
  Rig rig(CoverageMode::Systematic);
  std::vector<std::uint8_t> echo = rig.static_cells;
  for (int j = 1; j + 1 < kNy; ++j) {
    for (int i = 1; i + 1 < kNx; ++i) {
      const std::size_t k = std::size_t(j * kNx + i);
      if (rig.static_cells[k] == cost::kLethal) continue;
      for (const int d : {-1, 1, -kNx, kNx}) {
        if (rig.static_cells[std::size_t(std::ptrdiff_t(k) + d)] == cost::kLethal) {
          echo[k] = cost::kLethal;
        }
      }
    }
  }
  rig.costmap.build(echo);
  rig.start();
  const Result r = rig.run(600.0);
  ASSERT_EQ(rig.mission->current(), CoverageMission::State::Done);
  const double covered =
      covered_and_report("systematic, walls a cell thicker in the costmap", rig, r);
  EXPECT_GE(covered, 0.95);
  EXPECT_EQ(r.collisions, 0);
  MissionCounters c;
  rig.mission->counters(c);
  EXPECT_EQ(c[2].value, 0u);  // no lane blocked
}

TEST(CoverageMissionTest, VacuumBacksUpAndTurnsOnABumpBothWaysOverSeeds) {
  std::uint32_t left = 0, right = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    Rig rig(CoverageMode::Vacuum);
    rig.cfg.seed = seed;
    rig.cfg.max_time_s = 60.0;
    rig.start();
    const Result r = rig.run(61.0);
    EXPECT_TRUE(r.backed_up_after_bump) << "seed " << seed;
    EXPECT_TRUE(r.turned_after_backup) << "seed " << seed;
    EXPECT_GE(rig.mission->bumps(), 1u);
    EXPECT_EQ(rig.mission->current(), CoverageMission::State::Done);  // max_time_s
    EXPECT_EQ(r.collisions, 0) << "seed " << seed;
    left += rig.mission->turns_left();
    right += rig.mission->turns_right();
  }
  EXPECT_GT(left, 0u);
  EXPECT_GT(right, 0u);
}

// The baseline's figures on the same map: covered within the systematic mode's time budget
// (1.3x the lower bound) and within 3x.
TEST(CoverageMissionTest, VacuumFiguresOnTheSameMap) {
  Rig probe(CoverageMode::Systematic);
  probe.start();
  probe.run(0.5);  // the reachable area is known after the first plan
  const std::vector<std::uint8_t> mask = reachable_truth(probe);
  std::size_t cells = 0;
  covered_of(*probe.mission, mask, &cells);
  const double lb = lower_bound_s(cells, probe.cfg);
  for (const double factor : {1.3, 3.0}) {
    Rig rig(CoverageMode::Vacuum);
    rig.cfg.max_time_s = factor * lb;
    rig.start();
    const Result r = rig.run(factor * lb + 1.0);
    const double covered = covered_of(*rig.mission, mask);
    report(factor < 2.0 ? "vacuum, 1.3x lower bound" : "vacuum, 3x lower bound", rig, r, covered,
           lb);
    EXPECT_EQ(r.collisions, 0);
    EXPECT_GT(covered, 0.1);
  }
}

TEST(CoverageMissionTest, UpdateDoesNotAllocate) {
  Rig rig(CoverageMode::Systematic, {Box{1.4, 1.2, 1.8, 1.7}});
  rig.start();
  rig.count_allocations = true;
  rig.run(400.0);
  EXPECT_EQ(rig.mission->current(), CoverageMission::State::Done);
  EXPECT_GT(rig.mission->coverage().covered_cells(), 1000u);
  EXPECT_EQ(alloc::count_in_windows(), 0u);
  Rig vac(CoverageMode::Vacuum);
  vac.start();
  vac.count_allocations = true;
  vac.run(30.0);
  EXPECT_EQ(alloc::count_in_windows(), 0u);
}

TEST(CoverageMissionTest, AMapWithNoFreeCellFailsWithAClearErrorAndAFault) {
  Rig rig(CoverageMode::Systematic);
  std::vector<std::uint8_t> walls(std::size_t(kNx * kNy), cost::kLethal);
  ASSERT_TRUE(rig.map.assign(map_info(), walls.data()).is_ok());
  rig.start();
  const Status& s = rig.mission->init_status();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(std::string(s.message()).find("no free cell"), std::string::npos) << s.message();
  const Result r = rig.run(1.0);
  (void)r;
  EXPECT_EQ(rig.mission->state().status, MissionStatus::Failed);
  MissionOutput out = rig.mission->update(rig.ctx);
  EXPECT_EQ(out.fault, Fault::NoCoverageArea);
  EXPECT_EQ(out.motion.twist.vx, 0.0);
  EXPECT_EQ(out.motion.twist.wz, 0.0);

  // No static map at all: the systematic mode cannot plan.
  OccupancyGrid none;
  Topic<OdometryMsg> pose;
  TestCostmap costmap;
  Topic<CostmapMsg> costmap_topic{CostmapMsg{&costmap}};
  CoverageConfig cfg;
  SystematicCoverage m(cfg, Footprint{0.25, 0.25}, false, pose, costmap_topic, none);
  EXPECT_NE(std::string(m.init_status().message()).find("no static map"), std::string::npos);
}

// The two modes are two missions on one base: make_coverage_mission() builds the mode's, and only
// the systematic one needs a map to plan on.
TEST(CoverageMissionTest, EachModeIsItsOwnMission) {
  OccupancyGrid none;
  Topic<OdometryMsg> pose;
  TestCostmap costmap;
  Topic<CostmapMsg> costmap_topic{CostmapMsg{&costmap}};
  CoverageConfig cfg;
  cfg.mode = CoverageMode::Systematic;
  auto systematic =
      make_coverage_mission(cfg, Footprint{0.25, 0.25}, false, pose, costmap_topic, none);
  EXPECT_NE(dynamic_cast<SystematicCoverage*>(systematic.get()), nullptr);
  EXPECT_FALSE(systematic->init_status().is_ok());
  cfg.mode = CoverageMode::Vacuum;
  auto vacuum = make_coverage_mission(cfg, Footprint{0.25, 0.25}, false, pose, costmap_topic, none);
  EXPECT_NE(dynamic_cast<VacuumCoverage*>(vacuum.get()), nullptr);
  EXPECT_TRUE(vacuum->init_status().is_ok());  // blind to the map: it only cannot count coverage
  EXPECT_STREQ(vacuum->name(), "coverage");
}

TEST(CoverageMissionTest, ARobotSealedOffFromTheAreaFailsWithNoPath) {
  Rig rig(CoverageMode::Systematic);
  // A polygon round the right room only, the door closed in the map: nothing reachable.
  std::vector<std::uint8_t> closed = two_rooms({Box{3.0, 1.3, 3.1, 2.4}});
  ASSERT_TRUE(rig.map.assign(map_info(), closed.data()).is_ok());
  rig.costmap.build(closed);
  rig.cfg.area.push_back(Vec2(3.1, 0.1));
  rig.cfg.area.push_back(Vec2(6.1, 0.1));
  rig.cfg.area.push_back(Vec2(6.1, 3.5));
  rig.cfg.area.push_back(Vec2(3.1, 3.5));
  rig.start();
  ASSERT_TRUE(rig.mission->init_status().is_ok()) << rig.mission->init_status().message();
  const Result r = rig.run(5.0);
  (void)r;
  EXPECT_EQ(rig.mission->state().status, MissionStatus::Failed);
  EXPECT_EQ(rig.mission->update(rig.ctx).fault, Fault::NoPath);
}

}  // namespace
}  // namespace carril::fw
