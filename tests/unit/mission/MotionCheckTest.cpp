// The swept-footprint check every motion passes: what it stops, what it only slows, and the
// nearest clear motion it puts in place of one that is not clear (a turn into a wall beside, a
// tight U-turn at a wall), judged on a lidar's returns from a scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "firmware/mission/MotionCheck.hpp"
#include "tests/unit/mission/SafetyRig.hpp"

namespace carril::fw {
namespace {

const Footprint kDisc{0.171, 0.171};  // a cleaner: round_body
const Footprint kBox{0.3, 0.2};

SafetyFieldsConfig fields() {
  return test::safety_fields_config();
}

// A wall along x at y = -(half width + gap): the robot runs along it on its right.
test::ScanScene wall_right(const Footprint& fp, double gap_m) {
  test::ScanScene s;
  const double y = -(fp.half_width_m + gap_m);
  s.segments.push_back({Vec2(-2.0, y), Vec2(3.0, y)});
  return s;
}

// A wall across the way at x = half length + gap.
test::ScanScene wall_ahead(const Footprint& fp, double gap_m) {
  test::ScanScene s;
  const double x = fp.half_length_m + gap_m;
  s.segments.push_back({Vec2(x, -2.0), Vec2(x, 2.0)});
  return s;
}

MotionVerdict judge(const Footprint& fp, bool round, const test::ScanScene& scene,
                    const Twist& want, bool alternatives = true) {
  MotionCheckConfig c;
  c.round_body = round;
  c.alternatives = alternatives;
  MotionCheck check(c, fields(), fp);
  const ObstacleField f = test::field_of(fp, scene);
  return check.check(want, Pose2{}, f, Pose2{}, std::hypot(want.vx, want.vy), want.wz);
}

TEST(MotionCheckTest, NothingNearPassesTheRequestUnchanged) {
  const MotionVerdict v = judge(kBox, false, wall_ahead(kBox, 3.0), Twist{0.5, 0.0, 0.2});
  EXPECT_TRUE(v.clear);
  EXPECT_FALSE(v.alternative);
  EXPECT_EQ(v.scale, 1.0);
  EXPECT_EQ(v.twist.vx, 0.5);
  EXPECT_EQ(v.twist.wz, 0.2);
}

TEST(MotionCheckTest, AWallAheadCutsTheSpeedToAStopThatFitsAndAtThePadStops) {
  // 10 cm ahead at 0.5 m/s (a 0.165 m reach): slowed to what stops in the free travel.
  const MotionVerdict slow = judge(kBox, false, wall_ahead(kBox, 0.10), Twist{0.5, 0.0, 0.0});
  EXPECT_TRUE(slow.clear);
  EXPECT_LT(slow.scale, 1.0);
  EXPECT_GT(slow.scale, 0.0);
  const SafetyFieldsConfig f = fields();
  const double v = 0.5 * slow.scale;
  EXPECT_LE(v * 2.0 * f.reaction_s() + v * v / (2.0 * f.decel_mps2), slow.free_m + 1e-9);
  // Within the pad (2 cm of a 3 cm pad): straight into it is stopped, backing away is not.
  const MotionVerdict in = judge(kBox, false, wall_ahead(kBox, 0.02), Twist{0.2, 0.0, 0.0});
  EXPECT_FALSE(in.clear);
  EXPECT_EQ(in.twist.vx, 0.0);
  EXPECT_TRUE(judge(kBox, false, wall_ahead(kBox, 0.02), Twist{-0.2, 0.0, 0.0}).clear);
}

// The disc robot driven for `seconds` at 100 Hz by what the check makes of the same request
// every tick, from `start`, the scene scanned afresh from each pose.
struct Drive {
  double min_gap_m = 1e9;  // the body's least gap to the scene's segments [m]
  double travelled_m = 0.0;
  double turned_rad = 0.0;
  int alternatives = 0, stops = 0, cut = 0;
};

double gap_to(const test::ScanScene& scene, const Vec2& p, double radius) {
  double best = 1e9;
  for (const auto& s : scene.segments) {
    const Vec2 e = s.b - s.a;
    const double u = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::fmin(best, (s.a + u * e - p).norm());
  }
  return best - radius;
}

Drive drive(const test::ScanScene& scene, const Twist& want, double seconds, Pose2 pose = {}) {
  MotionCheckConfig c;
  c.round_body = true;
  MotionCheck check(c, fields(), kDisc);
  ObstacleField f(kDisc, 0.0, 0.0, 0.0);
  Drive d;
  Twist now{};
  for (int i = 0; i < int(seconds * 100.0); ++i) {
    auto s = scene.scan(pose, Pose2{}, 1441, 2.0 * kPi);
    s->seq = std::uint32_t(i + 1);
    f.update(*s, pose);
    const MotionVerdict v = check.check(want, pose, f, pose, std::hypot(now.vx, now.vy), now.wz);
    d.alternatives += v.alternative ? 1 : 0;
    d.stops += v.clear ? 0 : 1;
    d.cut += v.clear && !v.alternative && v.scale < 1.0 ? 1 : 0;
    now = v.twist;
    const double dt = 0.01;
    pose.x += now.vx * std::cos(pose.yaw) * dt;
    pose.y += now.vx * std::sin(pose.yaw) * dt;
    pose.yaw += now.wz * dt;
    d.travelled_m += std::fabs(now.vx) * dt;
    d.turned_rad += std::fabs(now.wz) * dt;
    d.min_gap_m = std::fmin(d.min_gap_m, gap_to(scene, Vec2(pose.x, pose.y), kDisc.half_width_m));
  }
  return d;
}

TEST(MotionCheckTest, ARobotRunningAlongAWallInsideThePadGoesOnButMayNotTurnIntoIt) {
  // 1.5 cm from a wall on the right, inside the 3 cm pad: straight along it goes on at full
  // speed (the wall's returns ahead may come as near as the wall beside already is).
  const test::ScanScene wall = wall_right(kDisc, 0.015);
  const MotionVerdict along = judge(kDisc, true, wall, Twist{0.3, 0.0, 0.0});
  EXPECT_TRUE(along.clear);
  EXPECT_FALSE(along.alternative);
  EXPECT_EQ(along.scale, 1.0);
  // Turning away from it: as requested.
  const MotionVerdict away = judge(kDisc, true, wall, Twist{0.3, 0.0, 0.5});
  EXPECT_TRUE(away.clear);
  EXPECT_FALSE(away.alternative);
  // A tight turn into it, asked for tick after tick: slowed as it nears, then replaced by the
  // nearest clear motion (less turn, or the turn on the spot); it never comes within the touch
  // floor (5 mm, less a tick's travel) and is never left standing at the wall.
  const Drive into = drive(wall, Twist{0.3, 0.0, -2.0}, 3.0);
  EXPECT_GT(into.cut, 0);
  EXPECT_GT(into.alternatives, 50);
  EXPECT_GT(into.min_gap_m, 0.003);
  EXPECT_EQ(into.stops, 0);
  EXPECT_GT(into.travelled_m, 0.25);
  // Without alternatives the same request ends stopped at the wall.
  const MotionVerdict stopped =
      judge(kDisc, true, wall_right(kDisc, 0.005), Twist{0.3, 0.0, -2.0}, false);
  EXPECT_FALSE(stopped.clear);
  EXPECT_EQ(stopped.twist.vx, 0.0);
  EXPECT_EQ(stopped.twist.wz, 0.0);
}

TEST(MotionCheckTest, ATightUTurnBlockedAtItsBulgeIsMadeOnTheSpot) {
  // A lane's end 3.5 cm short of a wall; the U-turn's arc (radius 0.12 m) bulges into it at
  // once. The round body turns on the spot rather than creep straight at the wall.
  const test::ScanScene wall = wall_ahead(kDisc, 0.035);
  const MotionVerdict v = judge(kDisc, true, wall, Twist{0.23, 0.0, 1.9});
  EXPECT_TRUE(v.clear);
  EXPECT_TRUE(v.alternative);
  EXPECT_EQ(v.twist.vx, 0.0);
  EXPECT_EQ(v.twist.wz, 1.9);
  // Asked for tick after tick, the U-turn is made (half a turn and more) and the body keeps
  // clear of the wall.
  const Drive u = drive(wall, Twist{0.23, 0.0, 1.9}, 3.0);
  EXPECT_GT(u.turned_rad, kPi);
  EXPECT_GT(u.min_gap_m, 0.003);
  EXPECT_EQ(u.stops, 0);
}

TEST(MotionCheckTest, ASquareBodysTurnOnTheSpotIsCheckedOnItsCorners) {
  // A box just past the front-left corner's circle: a turn is stopped, a disc's would not be.
  test::ScanScene s;
  s.discs.push_back({Vec2(0.3, 0.3), 0.05});
  const MotionVerdict square = judge(kBox, false, s, Twist{0.0, 0.0, 1.0});
  EXPECT_TRUE(square.turn);
  EXPECT_FALSE(square.clear);
  EXPECT_EQ(square.twist.wz, 0.0);
  const MotionVerdict disc = judge(kDisc, true, s, Twist{0.0, 0.0, 1.0});
  EXPECT_TRUE(disc.clear);
}

}  // namespace
}  // namespace carril::fw
