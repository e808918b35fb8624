// The wheels on the height field: attitude on slopes (pitch positive nose up, roll left side
// up), steps and slopes beyond the limits block once per contact, drops beyond the limit fall.
#include "host_sim/world/TerrainContact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace carril::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

RobotSpec pioneer() {
  RobotSpec r;  // the pioneer3at preset's geometry and terrain limits
  r.wheelbase_m = 0.268;
  r.track_m = 0.394;
  r.wheel_radius_m = 0.1105;
  r.terrain_limits = {19.0, 0.10, 0.15};
  return r;
}

TerrainSpec ramp(Vec2 c, double yaw_deg, double angle, double len) {
  TerrainSpec t;
  t.type = TerrainType::Ramp;
  t.center = c;
  t.yaw_rad = yaw_deg * kDeg;
  t.angle_deg = angle;
  t.length_m = len;
  t.width_m = 4.0;
  t.descend = false;
  return t;
}

TerrainSpec step(Vec2 c, double len, double h) {
  TerrainSpec t;
  t.type = TerrainType::Step;
  t.center = c;
  t.length_m = len;
  t.width_m = 4.0;
  t.height_m = h;
  return t;
}

// Drives straight along x from x0 to x1 in 2.5 mm moves (a 0.5 m/s robot's physics sub-step),
// standing still where a move is blocked. Returns the x reached.
double drive(TerrainContact& tc, double x0, double x1, double yaw, int& collisions, int& falls) {
  double x = x0;
  const double dx = x1 > x0 ? 0.0025 : -0.0025;
  const long moves = std::lround((x1 - x0) / dx);  // a fixed count: blocked moves count too
  for (long i = 0; i < moves; ++i) {
    const TerrainStep s = tc.move_to({x + dx, 0.0, yaw});
    collisions += s.new_collision ? 1 : 0;
    falls += s.new_fall ? 1 : 0;
    if (!s.blocked) x += dx;
  }
  return x;
}

TEST(TerrainContact, PitchOnAFiveDegreeRampUpAndDown) {
  const HeightField f({ramp({0, 0}, 0.0, 5.0, 4.0)}, {});  // rises toward +x, x = -2 .. 2
  TerrainContact tc(f, pioneer());
  tc.reset({0.0, 0.0, 0.0});  // facing uphill
  EXPECT_NEAR(tc.attitude().pitch_rad / kDeg, 5.0, 0.2);
  EXPECT_NEAR(tc.attitude().roll_rad, 0.0, 1e-9);
  EXPECT_NEAR(tc.attitude().z_m, 2.0 * std::tan(5.0 * kDeg), 0.02);
  tc.reset({0.0, 0.0, std::numbers::pi});  // facing downhill
  EXPECT_NEAR(tc.attitude().pitch_rad / kDeg, -5.0, 0.2);
}

TEST(TerrainContact, RollOnASideSlope) {
  // Rises toward +y: the robot facing +x has its left side up.
  const HeightField f({ramp({0, 0}, 90.0, 8.0, 4.0)}, {});
  TerrainContact tc(f, pioneer());
  tc.reset({0.0, 0.0, 0.0});
  EXPECT_NEAR(tc.attitude().roll_rad / kDeg, 8.0, 0.2);
  EXPECT_NEAR(tc.attitude().pitch_rad, 0.0, 1e-9);
  tc.reset({0.0, 0.0, std::numbers::pi});
  EXPECT_NEAR(tc.attitude().roll_rad / kDeg, -8.0, 0.2);
}

TEST(TerrainContact, HighStepBlocksOnceLowStepIsClimbed) {
  const HeightField high({step({2, 0}, 2.0, 0.2)}, {});  // edge at x = 1
  TerrainContact tc(high, pioneer());
  tc.reset({0.0, 0.0, 0.0});
  int collisions = 0, falls = 0;
  const double x = drive(tc, 0.0, 2.0, 0.0, collisions, falls);
  // Stopped with the front tyre (wheel centre + r) at the edge.
  EXPECT_NEAR(x, 1.0 - 0.134 - 0.1105, 0.005);
  EXPECT_EQ(collisions, 1);
  EXPECT_EQ(falls, 0);
  EXPECT_EQ(tc.attitude().z_m, 0.0);
  // Backing off and driving in again is a second contact.
  drive(tc, x, x - 0.1, 0.0, collisions, falls);
  drive(tc, x - 0.1, 2.0, 0.0, collisions, falls);
  EXPECT_EQ(collisions, 2);

  const HeightField low({step({2, 0}, 2.0, 0.01)}, {});
  TerrainContact tc2(low, pioneer());
  tc2.reset({0.0, 0.0, 0.0});
  collisions = 0;
  EXPECT_NEAR(drive(tc2, 0.0, 2.0, 0.0, collisions, falls), 2.0, 1e-9);
  EXPECT_EQ(collisions, 0);
  EXPECT_EQ(tc2.attitude().z_m, 0.01);
}

TEST(TerrainContact, StepAtTheLimitIsClimbedAboveItBlocks) {
  for (const double h : {0.10, 0.101}) {
    const HeightField f({step({2, 0}, 2.0, h)}, {});
    TerrainContact tc(f, pioneer());
    tc.reset({0.0, 0.0, 0.0});
    int collisions = 0, falls = 0;
    drive(tc, 0.0, 2.0, 0.0, collisions, falls);
    EXPECT_EQ(collisions, h > 0.1 ? 1 : 0) << h;
  }
}

TEST(TerrainContact, SteepRampBlocksGentleOneIsDriven) {
  int collisions = 0, falls = 0;
  const HeightField steep({ramp({2, 0}, 0.0, 25.0, 2.0)}, {});  // foot at x = 1
  TerrainContact tc(steep, pioneer());
  tc.reset({0.0, 0.0, 0.0});
  EXPECT_NEAR(drive(tc, 0.0, 2.0, 0.0, collisions, falls), 1.0 - 0.134 - 0.1105, 0.005);
  EXPECT_EQ(collisions, 1);

  const HeightField gentle({ramp({2, 0}, 0.0, 18.0, 2.0)}, {});
  TerrainContact tc2(gentle, pioneer());
  tc2.reset({0.0, 0.0, 0.0});
  collisions = 0;
  EXPECT_NEAR(drive(tc2, 0.0, 2.0, 0.0, collisions, falls), 2.0, 1e-9);
  EXPECT_EQ(collisions, 0);
  EXPECT_NEAR(tc2.attitude().pitch_rad / kDeg, 18.0, 0.2);
}

TEST(TerrainContact, DropBeyondTheLimitIsOneFall) {
  // Start on a 0.2 m platform (x = -2 .. 2) and drive off its edge: one fall for all four wheels.
  const HeightField f({step({0, 0}, 4.0, 0.2)}, {});
  TerrainContact tc(f, pioneer());
  tc.reset({0.0, 0.0, 0.0});
  EXPECT_EQ(tc.attitude().z_m, 0.2);
  int collisions = 0, falls = 0;
  EXPECT_NEAR(drive(tc, 0.0, 3.0, 0.0, collisions, falls), 3.0, 1e-9);
  EXPECT_EQ(falls, 1);
  EXPECT_EQ(collisions, 1);
  EXPECT_EQ(tc.attitude().z_m, 0.0);

  // A 0.1 m drop is within the pioneer's 0.15 m: driven down, no fall.
  const HeightField low({step({0, 0}, 4.0, 0.1)}, {});
  TerrainContact tc2(low, pioneer());
  tc2.reset({0.0, 0.0, 0.0});
  collisions = falls = 0;
  drive(tc2, 0.0, 3.0, 0.0, collisions, falls);
  EXPECT_EQ(falls, 0);
  EXPECT_EQ(collisions, 0);
}

}  // namespace
}  // namespace carril::sim
