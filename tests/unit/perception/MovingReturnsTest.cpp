// MovingReturns: a return lying where an older scan saw free space is something that moved in
// (a person crossing); a wall the robot's own motion brings into view, or one seen at a grazing
// angle, is not.
#include "firmware/perception/MovingReturns.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/unit/perception/ScanScene.hpp"

namespace carril::fw {
namespace {

constexpr double kRate = 20.0;  // scans per second
const Footprint kBody{0.25, 0.25};
const Pose2 kMount{0.2, 0.0, 0.0};

struct Rig {
  MovingReturnsConfig cfg;
  ObstacleField field{kBody, kMount.x, kMount.y, kMount.yaw};
  MovingReturns moving{cfg, kRate};

  // One scan of `scene` from `pose`; returns how many returns were marked moving.
  std::size_t scan(const test::ScanScene& scene, const Pose2& pose) {
    auto s = scene.scan(pose, kMount, 721, 270.0 * kPi / 180.0);
    field.update(*s, pose);
    moving.classify(*s, pose, field);
    return field.moving_count();
  }
};

// A corridor 2 m wide with a wall across it 6 m on, and a pillar on the left.
test::ScanScene corridor() {
  test::ScanScene s;
  s.segments.push_back({Vec2(-5.0, 1.0), Vec2(6.0, 1.0)});
  s.segments.push_back({Vec2(-5.0, -1.0), Vec2(6.0, -1.0)});
  s.segments.push_back({Vec2(6.0, -1.0), Vec2(6.0, 1.0)});
  s.discs.push_back({Vec2(2.0, 0.7), 0.15});
  return s;
}

TEST(MovingReturnsTest, LooksBackAboutHistorySecondsOfScans) {
  Rig r;
  EXPECT_EQ(r.moving.depth(), 5);  // 0.25 s at 20 Hz
  MovingReturnsConfig c;
  c.history_s = 10.0;
  EXPECT_EQ(MovingReturns(c, kRate).depth(), MovingReturns::kMaxHistory - 1);
}

TEST(MovingReturnsTest, StaticWallsStayStaticWhileTheRobotDrivesAndTurns) {
  Rig r;
  const test::ScanScene scene = corridor();
  std::size_t marked = 0;
  // 4 s at 0.8 m/s, weaving: walls at grazing angles, the pillar revealing the wall behind it.
  for (int k = 0; k < 80; ++k) {
    const double t = k / kRate;
    const Pose2 p{0.8 * t - 1.0, 0.3 * std::sin(t), 0.4 * std::sin(1.5 * t)};
    marked += r.scan(scene, p);
  }
  EXPECT_EQ(marked, 0U);
}

TEST(MovingReturnsTest, APersonWalkingAcrossIsMovingAsAWhole) {
  Rig r;
  test::ScanScene scene = corridor();
  scene.discs.push_back({Vec2(3.0, -0.8), 0.2});  // a person, 3 m ahead, against the right wall
  std::size_t last = 0;
  int marked_scans = 0;
  for (int k = 0; k < 20; ++k) {
    // Standing for 0.5 s, then walking across at 1.2 m/s.
    const double t = k / kRate;
    scene.discs.back().c.y() = -0.75 + (t > 0.5 ? 1.2 * (t - 0.5) : 0.0);
    last = r.scan(scene, Pose2{});
    if (last > 0) ++marked_scans;
    if (t <= 0.5) EXPECT_EQ(last, 0U) << "standing still, scan " << k;
  }
  // Every return of the person, not only its leading edge: at 1 m, a 0.4 m disc spans ~40 beams
  // of 0.375 deg, of which the near half shows.
  EXPECT_GE(last, 15U);
  EXPECT_GE(marked_scans, 8);
  // Only the person: each marked return lies on it.
  for (std::size_t i = 0; i < r.field.points().size(); ++i) {
    if (!r.field.moving(i)) continue;
    EXPECT_LT((r.field.points()[i] - scene.discs.back().c).norm(), 0.25);
  }
}

TEST(MovingReturnsTest, ASlowDriftWithinTheMarginIsNotMoving) {
  Rig r;
  test::ScanScene scene = corridor();
  scene.discs.push_back({Vec2(3.0, 0.0), 0.2});
  std::size_t marked = 0;
  for (int k = 0; k < 40; ++k) {
    scene.discs.back().c.x() = 3.0 - 0.1 * k / kRate;  // 0.1 m/s toward the robot
    marked += r.scan(scene, Pose2{});
  }
  EXPECT_EQ(marked, 0U);  // 2.5 cm in 0.25 s, under the 8 cm margin
}

TEST(MovingReturnsTest, OlderBeamsThatSaidNothingMarkNothing) {
  Rig r;
  test::ScanScene scene = corridor();
  auto blind = scene.scan(Pose2{}, kMount, 721, 270.0 * kPi / 180.0);
  for (int i = 0; i < blind->count; ++i) blind->ranges_m[std::size_t(i)] = std::nanf("");
  for (int k = 0; k < 6; ++k) {
    r.field.update(*blind, Pose2{});
    r.moving.classify(*blind, Pose2{}, r.field);
  }
  scene.discs.push_back({Vec2(1.5, 0.0), 0.2});  // appears where the NaN beams looked
  EXPECT_EQ(r.scan(scene, Pose2{}), 0U);
  EXPECT_GT(r.field.points().size(), 100U);
}

// A wall coming into range as the robot drives up to it: near range_max the range noise alone
// decides whether a beam returned (an older beam said "no return" where the new one hits), and
// that says nothing about motion. Before the margin applied to "no return", the thesis course
// corners marked 24 returns of its far wall, 20 m away, moving.
TEST(MovingReturnsTest, AFarWallComingIntoRangeIsNotMoving) {
  Rig r;
  test::ScanScene scene;
  scene.segments.push_back({Vec2(20.4, -4.0), Vec2(20.4, 4.0)});
  std::size_t marked = 0;
  for (int k = 0; k < 40; ++k) {
    const Pose2 p{0.5 * k / kRate, 0.0, 0.0};  // 0.5 m/s toward it: 20.2 m to 19.2 m
    auto sc = scene.scan(p, kMount, 721, 270.0 * kPi / 180.0, 40.0);
    sc->range_max_m = 20.0F;
    // Range noise, 2 cm long in one scan and short in the next (the worst case of a 1 cm
    // sigma), then cut at range_max as a lidar does.
    const float bias = (k % 2 == 0) ? 0.02F : -0.02F;
    for (int i = 0; i < sc->count; ++i) {
      float& v = sc->ranges_m[std::size_t(i)];
      v += bias;
      if (v > sc->range_max_m) v = std::numeric_limits<float>::infinity();
    }
    r.field.update(*sc, p);
    r.moving.classify(*sc, p, r.field);
    marked += r.field.moving_count();
  }
  EXPECT_EQ(marked, 0U);
}

TEST(MovingReturnsTest, ConfigValidateNamesTheField) {
  MovingReturnsConfig c;
  c.margin_m = -0.1;
  const Status s = c.validate();
  ASSERT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("lidar.moving.margin_m: -0.1 m, expected 0 to 1 m"),
            std::string::npos)
      << s.message();
}

}  // namespace
}  // namespace carril::fw
