// SimWorld over terrain, driven by a scripted twist (no firmware): blocked by a high step with
// one collision, climbs a low one, falls off a drop, pitches up a ramp, stopped by a steep one.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A pioneer3at at the origin facing +x over `terrain` (YAML list items).
Scenario terrain_scenario(const std::string& terrain) {
  return test::load_text(R"(
name: terrain
duration_s: 1
robot: {preset: pioneer3at}
mission: {type: follow_line, strategy: pid, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-20, -20], [-19, -20]]}]
terrain:
)" + terrain);
}

// Drives at vx [m/s] for t [s] in 5 ms physics steps (SimRun's two sub-steps of a 100 Hz tick).
void drive(SimWorld& w, const Scenario& s, double vx, double t) {
  fw::DriveKinematics kin(drive_geometry(s.robot));
  float wheels[hal::kMaxWheels] = {};
  kin.inverse({vx, 0.0, 0.0}, wheels);
  w.set_wheel_targets(wheels);
  for (int i = 0; i < int(std::lround(t / 0.005)); ++i) w.step(0.005);
}

TEST(SimWorldTerrain, HighStepBlocksWithOneCollisionLowStepIsClimbed) {
  const Scenario high =
      terrain_scenario("  - {type: step, x: 2, y: 0, length_m: 2, width_m: 3, height_m: 0.2}\n");
  SimWorld w(high);
  drive(w, high, 0.5, 6.0);  // 3 m if nothing stopped it
  EXPECT_EQ(w.collisions(), 1);
  EXPECT_EQ(w.falls(), 0);
  // The front tyre (wheel centre 0.134 m + radius 0.1105 m ahead of the centre) at the edge x = 1.
  EXPECT_NEAR(w.pose().x, 1.0 - 0.2445, 0.01);
  EXPECT_EQ(w.attitude().z_m, 0.0);
  double vx = 0, vy = 0, wz = 0;
  w.body_velocity(vx, vy, wz);
  EXPECT_EQ(vx, 0.0);  // the body stands, whatever its wheels do
  EXPECT_EQ(w.take_new_contacts().size(), 1U);

  const Scenario low =
      terrain_scenario("  - {type: step, x: 2, y: 0, length_m: 2, width_m: 3, height_m: 0.01}\n");
  SimWorld w2(low);
  drive(w2, low, 0.5, 4.0);
  EXPECT_EQ(w2.collisions(), 0);
  EXPECT_GT(w2.pose().x, 1.8);
  EXPECT_NEAR(w2.attitude().z_m, 0.01, 1e-12);
}

TEST(SimWorldTerrain, DrivingOffATwentyCentimetreDropIsAFall) {
  const Scenario s =
      terrain_scenario("  - {type: step, x: 0, y: 0, length_m: 4, width_m: 4, height_m: 0.2}\n");
  SimWorld w(s);
  EXPECT_EQ(w.attitude().z_m, 0.2);
  drive(w, s, 0.5, 6.0);
  EXPECT_EQ(w.falls(), 1);
  EXPECT_EQ(w.collisions(), 1);
  EXPECT_GT(w.pose().x, 2.8);  // it carries on at the lower level
  EXPECT_EQ(w.attitude().z_m, 0.0);
}

TEST(SimWorldTerrain, PitchFollowsAFiveDegreeHill) {
  // Up 5 deg over 3 m from x = 1, 1 m top, down again to x = 8.
  const Scenario s = terrain_scenario(
      "  - {type: ramp, x: 4.5, y: 0, length_m: 3, width_m: 3, angle_deg: 5, top_m: 1}\n");
  SimWorld w(s);
  drive(w, s, 0.5, 5.0);  // x = 2.5: all four wheels on the way up
  EXPECT_GT(w.pose().x, 2.3);
  EXPECT_NEAR(w.attitude().pitch_rad / kDeg, 5.0, 0.2);
  EXPECT_NEAR(w.attitude().roll_rad, 0.0, 1e-9);
  drive(w, s, 0.5, 7.0);  // x = 6: on the way down
  EXPECT_NEAR(w.attitude().pitch_rad / kDeg, -5.0, 0.2);
  drive(w, s, 0.5, 6.0);  // x = 9: off it
  EXPECT_EQ(w.attitude().pitch_rad, 0.0);
  EXPECT_EQ(w.collisions(), 0);
  EXPECT_EQ(w.falls(), 0);
}

TEST(SimWorldTerrain, TwentyFiveDegreeRampBlocks) {
  const Scenario s = terrain_scenario(
      "  - {type: ramp, x: 2, y: 0, length_m: 1, width_m: 3, angle_deg: 25, descend: false}\n");
  SimWorld w(s);
  drive(w, s, 0.5, 6.0);
  EXPECT_EQ(w.collisions(), 1);
  EXPECT_NEAR(w.pose().x, 1.5 - 0.2445, 0.01);
  EXPECT_EQ(w.attitude().pitch_rad, 0.0);
}

}  // namespace
}  // namespace carril::sim
