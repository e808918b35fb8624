// The Localisation component: without a map the pose is the odometry, bit for bit; on a map it
// starts where it is told, converges onto the true pose from the scans (held unlocalised until
// then) and allocates nothing in its ticks; kidnapped, it reports itself lost as soon as the
// scans stop fitting (before the spread widens), finds itself again and counts the jump; started
// with nothing known, it spreads again from a room that fits the scans only with returns through
// that room's walls.
#include "firmware/estimation/Localisation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

namespace carril::fw {
namespace {

// A 6 x 4 m room at 0.05 m, walls 0.1 m, a 1 x 0.5 m block off centre (no symmetry).
std::vector<std::uint8_t> room(MapInfo& info) {
  info = {120, 80, 0.05, -3.0, -2.0};
  std::vector<std::uint8_t> c(120 * 80, cost::kFree);
  for (int j = 0; j < 80; ++j) {
    for (int i = 0; i < 120; ++i) {
      const bool wall = i < 2 || j < 2 || i >= 118 || j >= 78;
      const bool block = i >= 80 && i < 100 && j >= 50 && j < 60;
      if (wall || block) c[std::size_t(j) * 120 + std::size_t(i)] = cost::kLethal;
    }
  }
  return c;
}

// A 360-beam, 360 deg scan from the pose, by a fine march through the grid.
hal::LaserScan scan_from(const OccupancyGrid& map, const Pose2& p, std::uint32_t seq) {
  hal::LaserScan s;
  s.seq = seq;
  s.count = 360;
  s.angle_min_rad = float(-kPi);
  s.angle_increment_rad = float(2.0 * kPi / 360.0);
  s.range_min_m = 0.05F;
  s.range_max_m = 8.0F;
  for (int k = 0; k < 360; ++k) {
    const double a = p.yaw + double(s.angle_min_rad) + k * double(s.angle_increment_rad);
    double r = 0.0;
    for (; r < 8.0; r += 0.005) {
      int i = 0, j = 0;
      if (!map.cell_of(p.x + r * std::cos(a), p.y + r * std::sin(a), i, j) ||
          map.at(i, j) == cost::kLethal) {
        break;
      }
    }
    s.ranges_m[std::size_t(k)] = float(r);
  }
  return s;
}

struct Rig {
  Topic<SensorFrame> frame;
  Topic<OdometryMsg> odom, pose;
  hal::LaserScan scan;
  void tick(Localisation& l, std::int64_t t_ns, const hal::LaserScan* s) {
    SensorFrame& f = frame.edit();
    f.now_ns = t_ns;
    f.scan = s;
    frame.publish(t_ns);
    odom.publish(odom.get(), t_ns);
    l.run();
  }
};

TEST(Localisation, WithoutAMapThePoseIsTheOdometryBitForBit) {
  Rig r;
  LocalisationConfig cfg;
  Localisation l(cfg, Pose2{}, nullptr, r.frame, r.odom, r.pose);
  r.odom.edit().pose = {1.0 / 3.0, -2.0 / 7.0, 3.1};
  r.tick(l, 0, nullptr);
  EXPECT_EQ(r.pose.get().pose.x, 1.0 / 3.0);
  EXPECT_EQ(r.pose.get().pose.y, -2.0 / 7.0);
  EXPECT_EQ(r.pose.get().pose.yaw, 3.1);
  EXPECT_TRUE(r.pose.get().localised);
}

TEST(Localisation, OnAMapItConvergesOntoTheTruePoseAndOnlyThenIsLocalised) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = room(info);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  const Pose2 truth{0.7, -0.4, 0.3};
  Rig r;
  LocalisationConfig cfg;
  cfg.enabled = true;
  cfg.initial_pose = {1.2, -0.1, 0.3 + 0.35};  // 0.58 m and 20 deg off
  cfg.initial_sigma_xy_m = 0.6;
  cfg.initial_sigma_yaw_rad = 0.4;
  cfg.mcl.max_particles = 2000;
  cfg.mcl.sigma_hit_m = 0.1;
  cfg.mcl.laser_max_range_m = 8.0;
  ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  Localisation l(cfg, Pose2{}, &map, r.frame, r.odom, r.pose);
  ASSERT_NE(l.filter(), nullptr);
  ASSERT_TRUE(l.filter()->status().is_ok()) << l.filter()->status().message();
  // The robot stands still at the true pose; its odometry starts at zero.
  std::vector<hal::LaserScan> scans;
  for (std::uint32_t k = 1; k <= 40; ++k) scans.push_back(scan_from(map, truth, k));
  r.tick(l, 0, nullptr);
  EXPECT_FALSE(r.pose.get().localised);  // no scan weighed yet
  alloc::begin_window();
  std::int64_t t = 0;
  for (const hal::LaserScan& s : scans) {
    for (int k = 0; k < 5; ++k) r.tick(l, t += 10'000'000, &s);  // 20 Hz scans, 100 Hz ticks
  }
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
  const Pose2& p = r.pose.get().pose;
  EXPECT_TRUE(r.pose.get().localised);
  EXPECT_LT(std::hypot(p.x - truth.x, p.y - truth.y), 0.1) << p.x << ", " << p.y;
  EXPECT_LT(std::abs(wrap_angle(p.yaw - truth.yaw)), 0.05) << p.yaw;
  EXPECT_GE(l.telemetry().updates, 1U);
  EXPECT_EQ(l.telemetry().lost, 0U);
}

// The robot turns in place (0.6 rad a scan: enough to update) at `at`, the odometry turning with
// it from `odom_yaw`; n scans, 5 ticks each. Returns the pose topic after each scan.
struct Turn {
  Rig& r;
  Localisation& l;
  const OccupancyGrid& map;
  std::int64_t t = 0;
  std::uint32_t seq = 0;
  double odom_yaw = 0.0;
  // Into `out` (reserved by the caller: nothing allocated here).
  void run(const Pose2& at, double& yaw, int n, std::vector<OdometryMsg>& out) {
    for (int k = 0; k < n; ++k) {
      yaw = wrap_angle(yaw + 0.6);
      odom_yaw = wrap_angle(odom_yaw + 0.6);
      r.odom.edit().pose = {0.0, 0.0, odom_yaw};
      const hal::LaserScan s = scan_from(map, {at.x, at.y, yaw}, ++seq);
      for (int i = 0; i < 5; ++i) r.tick(l, t += 10'000'000, &s);
      out.push_back(r.pose.get());
    }
  }
};

TEST(Localisation, AKidnapIsLostByTheFitBeforeTheSpreadWidensThenFoundAgainAsAJump) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = room(info);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  Rig r;
  LocalisationConfig cfg;
  cfg.enabled = true;
  cfg.initial_pose = {-1.5, 0.8, 0.0};  // told the truth
  cfg.initial_sigma_xy_m = 0.1;
  cfg.initial_sigma_yaw_rad = 0.1;
  cfg.mcl.max_particles = 3000;
  cfg.mcl.sigma_hit_m = 0.2;
  cfg.mcl.laser_max_range_m = 8.0;
  cfg.mcl.alpha_slow = 0.001;  // augmented MCL on (the MclConfig defaults)
  cfg.mcl.alpha_fast = 0.1;
  ASSERT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  Localisation l(cfg, Pose2{}, &map, r.frame, r.odom, r.pose);
  Turn turn{r, l, map};
  double yaw = 0.0;
  const Pose2 start{-1.5, 0.8, 0.0};
  std::vector<OdometryMsg> before, after;
  before.reserve(30);
  after.reserve(80);
  turn.run(start, yaw, 30, before);
  ASSERT_TRUE(before.back().localised);
  EXPECT_EQ(before.back().relocalisations, 0U);
  EXPECT_LT(std::hypot(before.back().pose.x - start.x, before.back().pose.y - start.y), 0.1);
  // Lifted across the room; the odometry knows nothing of it.
  const Pose2 there{1.6, -1.1, 0.0};
  alloc::begin_window();
  turn.run(there, yaw, 80, after);
  alloc::end_window();
  EXPECT_EQ(alloc::count_in_windows(), 0U);
  int lost_at = -1, found_at = -1;
  for (int k = 0; k < int(after.size()); ++k) {
    if (lost_at < 0 && !after[std::size_t(k)].localised) lost_at = k;
    if (lost_at >= 0 && found_at < 0 && after[std::size_t(k)].localised) found_at = k;
  }
  // Lost within 3 scans of the kidnap, by the fit: the cloud was still tight (within twice the
  // bounds) when the scans stopped fitting.
  ASSERT_GE(lost_at, 0);
  EXPECT_LE(lost_at, 3);
  EXPECT_EQ(l.telemetry().lost, 1U);
  EXPECT_EQ(l.telemetry().lost_by_fit, 1U);
  // Found again, where the robot is, and the jump is counted once (the costmap and the mission
  // read it); not localised in between.
  ASSERT_GT(found_at, lost_at) << "never found again";
  const OdometryMsg& last = after.back();
  EXPECT_TRUE(last.localised);
  EXPECT_LT(std::hypot(last.pose.x - there.x, last.pose.y - there.y), 0.1)
      << last.pose.x << ", " << last.pose.y;
  EXPECT_EQ(last.relocalisations, 1U);
  EXPECT_EQ(l.telemetry().relocalisations, 1U);
  for (int k = found_at; k < int(after.size()); ++k) {
    EXPECT_EQ(after[std::size_t(k)].relocalisations, 1U) << k;
  }
}

// Two 4.8 x 3.8 m rooms side by side at 0.05 m, apart (no door), the same 1 x 0.5 m block in the
// same corner of each; room B (x > 5) also has two free-standing partitions, 0.1 m thick, across
// its middle. From inside room A (no partitions) every return ends on a wall that room B has in
// the same place, so the likelihood field scores A and B alike; only in B do the returns pass
// through the partitions. Without `partitions` the rooms are alike in every way.
std::vector<std::uint8_t> two_rooms(MapInfo& info, bool partitions = true) {
  info = {200, 80, 0.05, 0.0, 0.0};
  std::vector<std::uint8_t> c(200 * 80, cost::kFree);
  for (int j = 0; j < 80; ++j) {
    for (int i = 0; i < 200; ++i) {
      const bool wall = i < 2 || j < 2 || i >= 198 || j >= 78 || (i >= 98 && i < 102);
      const int ri = i < 100 ? i : i - 100;  // the column within its room
      const bool block = ri >= 62 && ri < 82 && j >= 62 && j < 72;
      const bool partition =
          partitions && i >= 100 &&
          ((ri >= 48 && ri < 50 && j >= 10 && j < 66) || (j >= 52 && j < 54 && ri >= 8 && ri < 40));
      if (wall || block || partition) c[std::size_t(j) * 200 + std::size_t(i)] = cost::kLethal;
    }
  }
  return c;
}

// The two-room tests' filter: a 0.2 m hit model, no random injection (the loader's default);
// through_check false turns the walls check off.
LocalisationConfig two_rooms_config(bool through_check) {
  LocalisationConfig cfg;
  cfg.enabled = true;
  cfg.mcl.max_particles = 3000;
  cfg.mcl.sigma_hit_m = 0.2;
  cfg.mcl.laser_max_range_m = 8.0;
  cfg.mcl.alpha_slow = cfg.mcl.alpha_fast = 0.0;
  if (!through_check) cfg.regain_through_fraction = cfg.lost_through_fraction = 1.0;
  // Without the walls check room B is an alias of room A: the alias check would (rightly) hold
  // the robot unlocalised, and the test is of the walls check. With it, B is no alias.
  cfg.alias_check = through_check;
  return cfg;
}

// The robot turns in place in room A at (1.6, 1.5), n scans of 0.6 rad each: the published pose
// after each scan, and the telemetry at the end.
std::vector<OdometryMsg> turn_in_room_a(const OccupancyGrid& map, const LocalisationConfig& cfg,
                                        int n, LocalisationTelemetry& tel) {
  EXPECT_TRUE(cfg.validate().is_ok()) << cfg.validate().message();
  Rig r;
  Localisation l(cfg, Pose2{}, &map, r.frame, r.odom, r.pose);
  Turn turn{r, l, map};
  double yaw = 0.0;
  std::vector<OdometryMsg> out;
  out.reserve(std::size_t(n));
  turn.run({1.6, 1.5, 0.0}, yaw, n, out);
  tel = l.telemetry();
  return out;
}

// A global start in room A (150 scans): the localisation at the end and its telemetry.
struct GlobalRun {
  OdometryMsg last;
  LocalisationTelemetry tel;
  bool localised_in_b = false;  // localised at some scan with the pose in room B
};
GlobalRun global_start(const OccupancyGrid& map, std::uint64_t seed, bool through_check) {
  LocalisationConfig cfg = two_rooms_config(through_check);
  cfg.global = true;
  cfg.mcl.seed = seed;
  cfg.search_while_unlocalised = true;
  GlobalRun g;
  const std::vector<OdometryMsg> out = turn_in_room_a(map, cfg, 150, g.tel);
  for (const OdometryMsg& m : out) {
    g.localised_in_b = g.localised_in_b || (m.localised && m.pose.x > 5.0);
  }
  g.last = out.back();
  return g;
}

TEST(Localisation, AGlobalStartIsNotProvenInARoomWhoseWallsTheScansPassThrough) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = two_rooms(info);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  // The world is ambiguous to the likelihood: without the check some seeds end localised in B.
  int in_b_unchecked = 0, wrong = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    in_b_unchecked += global_start(map, seed, false).localised_in_b ? 1 : 0;
    const GlobalRun g = global_start(map, seed, true);
    EXPECT_FALSE(g.localised_in_b) << "seed " << seed;
    EXPECT_TRUE(g.last.localised) << "seed " << seed;
    EXPECT_LT(std::hypot(g.last.pose.x - 1.6, g.last.pose.y - 1.5), 0.15)
        << "seed " << seed << ": " << g.last.pose.x << ", " << g.last.pose.y;
    EXPECT_EQ(g.tel.spreads, g.tel.wrong_convergences) << "seed " << seed;
    wrong += int(g.tel.wrong_convergences);
  }
  EXPECT_GE(in_b_unchecked, 1) << "of 8 seeds: the test's rooms do not fool the filter";
  EXPECT_GE(wrong, 1) << "no seed converged in B first: the spread was never exercised";
}

// Rooms alike in every way: no view from room A tells it from room B. A global start is then
// never localised with the alias check (each search finds the other room and gives it to the
// filter as a hypothesis), while without it the filter settles on one room and calls itself
// localised there (in A or, as likely, in B).
TEST(Localisation, AGlobalStartAmongAlikeRoomsIsNeverLocalisedWithTheAliasCheck) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = two_rooms(info, false);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  int localised_unchecked = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    for (const bool alias_check : {true, false}) {
      LocalisationConfig cfg = two_rooms_config(true);
      cfg.alias_check = alias_check;
      cfg.global = true;
      cfg.mcl.seed = seed;
      cfg.search_while_unlocalised = true;
      LocalisationTelemetry tel;
      const std::vector<OdometryMsg> out = turn_in_room_a(map, cfg, 150, tel);
      int localised = 0;
      for (const OdometryMsg& m : out) localised += m.localised ? 1 : 0;
      if (alias_check) {
        EXPECT_EQ(localised, 0) << "seed " << seed;
        EXPECT_GE(tel.alias_ambiguous, 1U) << "seed " << seed;
        EXPECT_EQ(tel.alias_ambiguous, tel.alias_searches) << "seed " << seed;
        EXPECT_GE(tel.alias_hypotheses, 1U) << "seed " << seed;
        // The alias named is the same pose in the other room, 5 m along x.
        EXPECT_NEAR(std::abs(tel.alias.alias.x - tel.alias.pose.x), 5.0, 0.15) << "seed " << seed;
        EXPECT_NEAR(tel.alias.alias.y, tel.alias.pose.y, 0.15) << "seed " << seed;
      } else {
        EXPECT_EQ(tel.alias_searches, 0U);
        localised_unchecked += out.back().localised ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(localised_unchecked, 3) << "the rooms do not hold an unchecked filter back";
}

// Told it starts in room B where room A's robot would be (a wrong start the likelihood cannot
// tell from the right one): localised at once (a start given needs no proof), then lost by the
// returns through B's partitions, and never localised there again; without the check it stays
// localised in B. Returns the pose after each of 20 scans.
std::vector<OdometryMsg> told_room_b(const OccupancyGrid& map, bool through_check,
                                     LocalisationTelemetry& tel) {
  LocalisationConfig cfg = two_rooms_config(through_check);
  cfg.initial_pose = {6.6, 1.5, 0.0};
  cfg.initial_sigma_xy_m = 0.05;
  cfg.initial_sigma_yaw_rad = 0.05;
  cfg.mcl.max_particles = 2000;
  return turn_in_room_a(map, cfg, 20, tel);
}

TEST(Localisation, LocalisedWhereTheScansPassThroughTheMapsWallsItIsLost) {
  MapInfo info;
  const std::vector<std::uint8_t> cells = two_rooms(info);
  OccupancyGrid map(cells.size());
  ASSERT_TRUE(map.assign(info, cells.data()).is_ok());
  LocalisationTelemetry tel;
  // Localised from the first completed update on (the scan that begins it is weighed over ticks).
  const auto first_localised = [](const std::vector<OdometryMsg>& v) {
    for (int k = 0; k < int(v.size()); ++k) {
      if (v[std::size_t(k)].localised) return k;
    }
    return -1;
  };
  const std::vector<OdometryMsg> unchecked = told_room_b(map, false, tel);
  const int u0 = first_localised(unchecked);
  ASSERT_GE(u0, 0);
  EXPECT_LE(u0, 1);
  for (int k = u0; k < int(unchecked.size()); ++k) {
    EXPECT_TRUE(unchecked[std::size_t(k)].localised) << k;  // the likelihood is fooled
  }
  EXPECT_GT(unchecked.back().pose.x, 5.0);
  const std::vector<OdometryMsg> checked = told_room_b(map, true, tel);
  const int c0 = first_localised(checked);
  ASSERT_GE(c0, 0);
  EXPECT_LE(c0, 1);
  int lost_at = -1;
  for (int k = c0; k < int(checked.size()); ++k) {
    if (lost_at < 0 && !checked[std::size_t(k)].localised) lost_at = k;
    if (lost_at >= 0) EXPECT_FALSE(checked[std::size_t(k)].localised) << k;
  }
  ASSERT_GE(lost_at, 0);
  EXPECT_LE(lost_at - c0, 3);
  EXPECT_EQ(tel.lost, 1U);
  EXPECT_EQ(tel.lost_by_fit, 1U);  // still tight: the walls check, not the spread
  EXPECT_GT(tel.through_fraction, 0.3);
  EXPECT_EQ(tel.spreads, 0U);  // no recovery asked for
}

}  // namespace
}  // namespace carril::fw
