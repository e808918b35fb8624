// Lidar ray casts return known distances, from centred and off-centre rotated mounts, with the
// configured noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "hal/Types.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/sensors/RayCaster.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(LidarSimTest, CentreBeamMeasuresDistanceToBoxFace) {
  // pioneer3at lidar: at x = 0.20 on the centre line, facing forward, 180 deg, 361 beams.
  // Box face at x = 3.0 - 0.5 = 2.5 -> range 2.3 m on the beam at 0 deg (index 180).
  Scenario s = test::box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  auto scan = std::make_unique<hal::LaserScan>();
  lidar.scan(world, *scan);
  ASSERT_EQ(scan->count, 361);
  EXPECT_NEAR(scan->angle_min_rad, -90 * kDeg, 1e-6);
  EXPECT_NEAR(scan->angle_increment_rad, 0.5 * kDeg, 1e-6);
  EXPECT_NEAR(scan->ranges_m[180], 2.3, 1e-3);
  // 10 deg off-axis the ray still hits the face: 2.3 / cos(10 deg).
  EXPECT_NEAR(scan->ranges_m[200], 2.3 / std::cos(10 * kDeg), 1e-3);
  // Straight left there is nothing: no return is +inf.
  EXPECT_TRUE(std::isinf(scan->ranges_m[360]));
}

TEST(LidarSimTest, OffCentreRotatedMountSeesTheSameBox) {
  // campero lidar: mount (0.45, -0.35), heading -45 deg, 270 deg fov, 541 beams (0.5 deg).
  // The beam pointing along robot +x is at -(-45) = +45 deg in the sensor frame:
  // index (45 + 135) / 0.5 = 360. The box face is 2.5 - 0.45 = 2.05 m ahead of the mount.
  Scenario s = test::box_scenario("campero");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 1);
  auto scan = std::make_unique<hal::LaserScan>();
  lidar.scan(world, *scan);
  ASSERT_EQ(scan->count, 541);
  EXPECT_NEAR(scan->ranges_m[360], 2.05, 1e-3);
}

TEST(LidarSimTest, NoiseHasTheConfiguredSpread) {
  Scenario s = test::box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.02;
  SimWorld world(s);
  LidarSim lidar(s.robot.lidar, 3);
  auto scan = std::make_unique<hal::LaserScan>();
  double sum = 0, sum2 = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    lidar.scan(world, *scan);
    const double e = scan->ranges_m[180] - 2.3;
    sum += e;
    sum2 += e * e;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.005);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.004);
}

TEST(LidarSimTest, DroppedBeamsReportNoReturnAtTheRateAsked) {
  Scenario s = test::box_scenario("pioneer3at");
  s.robot.lidar.noise_std_m = 0.0;
  SimWorld world(s);
  auto scan = std::make_unique<hal::LaserScan>();
  LidarSim clean(s.robot.lidar, 1);
  clean.scan(world, *scan);
  const float before = scan->ranges_m[180];
  ASSERT_FALSE(std::isinf(before));
  s.robot.lidar.dropout = 0.3;
  LidarSim lossy(s.robot.lidar, 1);
  // Beam 180 sees the box: over 200 scans it is lost about 30 % of the time, else unchanged.
  int lost = 0;
  for (int k = 0; k < 200; ++k) {
    lossy.scan(world, *scan);
    if (std::isinf(scan->ranges_m[180])) {
      ++lost;
    } else {
      EXPECT_FLOAT_EQ(scan->ranges_m[180], before);
    }
  }
  EXPECT_NEAR(lost / 200.0, 0.3, 0.1);
}

// The closest-hit search RayCaster replaces: b2World::RayCast skipping the robot's body.
class ClosestHit : public b2RayCastCallback {
 public:
  explicit ClosestHit(const b2Body* self) : self_(self) {}
  float ReportFixture(b2Fixture* f, const b2Vec2&, const b2Vec2&, float fraction) override {
    if (f->GetBody() == self_) return -1.0F;
    if (fraction < best) best = fraction;
    return fraction;
  }
  float best = RayCaster::kNoHit;

 private:
  const b2Body* self_;
};

// A random world of `shapes` fixtures in a 40 m square: rotated and offset boxes, irregular
// polygons, circles, two-sided and one-sided edges, chains, a sensor, a disabled body, moving
// dynamic bodies and a multi-fixture static body (like the map walls); the returned robot box
// sits in the middle.
b2Body* random_world(b2World& w, int shapes, std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-20.0F, 20.0F), len(0.05F, 3.0F), ang(-3.2F, 3.2F);
  b2BodyDef walls_def;
  b2Body* walls = w.CreateBody(&walls_def);
  for (int k = 0; k < shapes; ++k) {
    b2BodyDef bd;
    bd.position.Set(pos(rng), pos(rng));
    bd.angle = ang(rng);
    if (k % 7 == 3) {  // static bodies must not be given a velocity: Box2D would move them
      bd.type = b2_dynamicBody;
      bd.linearVelocity.Set(len(rng), -len(rng));
      bd.angularVelocity = ang(rng);
    }
    b2Body* b = k % 5 == 4 ? walls : w.CreateBody(&bd);
    b2FixtureDef fd;
    fd.density = 1.0F;
    fd.isSensor = k % 11 == 6;
    b2PolygonShape box, poly;
    b2CircleShape disc;
    b2EdgeShape edge;
    b2ChainShape chain;
    const b2Vec2 c(pos(rng), pos(rng));
    switch (k % 6) {
      case 0:
        box.SetAsBox(len(rng), len(rng), b == walls ? c : b2Vec2(len(rng), 0.0F), ang(rng));
        fd.shape = &box;
        break;
      case 1: {
        b2Vec2 v[6];
        for (b2Vec2& p : v) p.Set(len(rng) * std::cos(ang(rng)), len(rng) * std::sin(ang(rng)));
        poly.Set(v, 6);
        fd.shape = &poly;
        break;
      }
      case 2:
        disc.m_radius = len(rng);
        disc.m_p = b == walls ? c : b2Vec2(0.0F, len(rng));
        fd.shape = &disc;
        break;
      case 3:
        edge.SetTwoSided(b2Vec2(-len(rng), 0.0F), b2Vec2(len(rng), len(rng)));
        fd.shape = &edge;
        break;
      case 4:
        edge.SetOneSided(b2Vec2(-4, -1), b2Vec2(-len(rng), 0.0F), b2Vec2(len(rng), 0.0F),
                         b2Vec2(4, -1));
        fd.shape = &edge;
        break;
      default: {
        const b2Vec2 v[5] = {{0, 0}, {len(rng), 0}, {len(rng), len(rng)}, {0, 3}, {-1, len(rng)}};
        if (k % 12 == 5) {
          chain.CreateLoop(v, 5);
        } else {
          chain.CreateChain(v, 5, b2Vec2(-1, -1), b2Vec2(-1, 4));
        }
        fd.shape = &chain;
      }
    }
    b->CreateFixture(&fd);
    if (k % 13 == 8 && b != walls) b->SetEnabled(false);  // no broad-phase proxy: never hit
  }
  for (int k = 0; k < 5; ++k) w.Step(0.1F, 8, 3);  // the dynamic bodies move off their start
  b2BodyDef rd;
  rd.type = b2_dynamicBody;
  b2Body* robot = w.CreateBody(&rd);
  b2PolygonShape body;
  body.SetAsBox(2.0F, 1.0F);
  robot->CreateFixture(&body, 1.0F);
  return robot;
}

// RayCaster against b2World::RayCast on random rays, from the robot and from anywhere: every
// fraction equal to the bit.
void expect_rays_match(b2World& w, const b2Body* robot, RayCaster& caster, std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-24.0F, 24.0F), len(0.1F, 40.0F), ang(-3.2F, 3.2F);
  int hits = 0, robot_crossings = 0;
  const int rays = 4000;
  for (int k = 0; k < rays; ++k) {
    // Half start on the robot's edge (as a lidar does) or just off it, half anywhere (inside
    // shapes too).
    const b2Vec2 p1 = k % 2 == 0 ? b2Vec2(k % 4 == 0 ? 2.0F : 2.3F, pos(rng) / 24.0F)
                                 : b2Vec2(pos(rng), pos(rng));
    const float a = ang(rng), l = len(rng);
    const b2Vec2 p2(p1.x + l * std::cos(a), p1.y + l * std::sin(a));
    ClosestHit want(robot);
    w.RayCast(&want, p1, p2);
    const float got = caster.cast(p1, p2);
    ASSERT_EQ(std::memcmp(&got, &want.best, sizeof got), 0)
        << "ray " << k << " (" << p1.x << ", " << p1.y << ") -> (" << p2.x << ", " << p2.y
        << "): caster " << got << ", Box2D " << want.best;
    hits += got <= 1.0F;
    ClosestHit any(nullptr);
    w.RayCast(&any, p1, p2);
    robot_crossings += any.best < want.best;
  }
  // The rays hit things often, and pass through the robot often: the test has teeth.
  EXPECT_GT(hits, rays / 8);
  EXPECT_GT(robot_crossings, 10);
}

// With few fixtures (plain list) and many (a grid over the static ones).
void expect_same_as_box2d(int shapes, unsigned seed) {
  std::mt19937 rng(seed);
  b2World w(b2Vec2(0.0F, 0.0F));
  const b2Body* robot = random_world(w, shapes, rng);
  RayCaster caster;
  caster.prepare(w, robot);
  ASSERT_EQ(caster.uses_grid(), shapes > 40);
  expect_rays_match(w, robot, caster, rng);
}

TEST(RayCasterTest, SameClosestHitAsBox2dWithFewFixtures) {
  // Up to the list's limit (kGridAbove candidates), where the boxes are tried nearest first.
  for (const int shapes : {8, 14, 20}) {
    for (unsigned seed = 7; seed <= 9; ++seed) expect_same_as_box2d(shapes, seed);
  }
}

TEST(RayCasterTest, SameClosestHitAsBox2dWithManyFixtures) {
  for (unsigned seed = 1; seed <= 3; ++seed) expect_same_as_box2d(300, seed);
}

// The static grid is kept while only the moving bodies move (as the map walls stay put while a
// lidar scans at 20 Hz), and rebuilt when a static body is moved or removed; the fractions match
// Box2D's each time.
TEST(RayCasterTest, TheStaticGridIsKeptUntilAStaticBodyChanges) {
  std::mt19937 rng(4);
  b2World w(b2Vec2(0.0F, 0.0F));
  const b2Body* robot = random_world(w, 300, rng);
  RayCaster caster;
  caster.prepare(w, robot);
  ASSERT_TRUE(caster.uses_grid());
  EXPECT_EQ(caster.grid_builds(), 1U);
  for (int k = 0; k < 3; ++k) {
    w.Step(0.1F, 8, 3);  // the dynamic bodies move on
    caster.prepare(w, robot);
    EXPECT_EQ(caster.grid_builds(), 1U) << "step " << k;
    expect_rays_match(w, robot, caster, rng);
  }
  b2Body* moved = nullptr;
  b2Body* removed = nullptr;
  for (b2Body* b = w.GetBodyList(); b != nullptr; b = b->GetNext()) {
    if (b->GetType() != b2_staticBody || b->GetFixtureList() == nullptr) continue;
    (moved == nullptr ? moved : removed) = b;
    if (removed != nullptr) break;
  }
  ASSERT_NE(removed, nullptr);
  moved->SetTransform(b2Vec2(1.0F, 12.0F), 0.7F);
  caster.prepare(w, robot);
  EXPECT_EQ(caster.grid_builds(), 2U);
  expect_rays_match(w, robot, caster, rng);
  w.DestroyBody(removed);
  caster.prepare(w, robot);
  EXPECT_EQ(caster.grid_builds(), 3U);
  expect_rays_match(w, robot, caster, rng);
}

}  // namespace
}  // namespace carril::sim
