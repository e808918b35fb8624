// SafetyFields: the stopping distance from speed, deceleration and reaction time; a protective
// field that stops, a warning field that slows for what moves, static returns judged in the band
// the body sweeps only, and directions the lidar cannot see driven slowly.
#include "firmware/mission/SafetyFields.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/unit/mission/SafetyRig.hpp"

namespace carril::fw {
namespace {

const Footprint kBody{0.25, 0.2};

SafetyFieldsConfig config() {
  return test::safety_fields_config();
}

ObstacleField field_of(const test::ScanScene& scene, double fov_deg = 360.0) {
  return test::field_of(kBody, scene, fov_deg);
}

test::ScanScene box_ahead(double gap_m, double y = 0.0) {
  test::ScanScene s;
  const double x = kBody.half_length_m + gap_m;
  s.segments.push_back({Vec2(x, y - 0.3), Vec2(x, y + 0.3)});
  return s;
}

TEST(SafetyFieldsTest, StoppingDistanceIsReactionPlusBrakingPlusMargin) {
  const SafetyFieldsConfig c = config();
  EXPECT_NEAR(c.reaction_s(), 0.08, 1e-12);
  EXPECT_NEAR(c.stop_m(0.0), 0.10, 1e-12);
  EXPECT_NEAR(c.stop_m(1.0), 0.08 + 0.5 + 0.10, 1e-12);
  EXPECT_NEAR(c.stop_m(1.5), 0.12 + 1.125 + 0.10, 1e-12);
  EXPECT_NEAR(c.stop_time_s(1.5), 1.58, 1e-12);
  EXPECT_NEAR(c.warning_m(1.0), 0.68 + 1.6 * 1.08, 1e-12);
  EXPECT_NEAR(c.warning_side_m(1.0), 0.05 + 1.6 * 1.08, 1e-12);
  // The caps invert them.
  for (double v : {0.05, 0.3, 0.7, 1.5}) {
    EXPECT_NEAR(c.static_cap_mps(c.static_stop_m(v) + v * c.reaction_s()), v, 1e-9);
    EXPECT_NEAR(c.warning_cap_mps(c.warning_m(v)), v, 1e-9);
    EXPECT_NEAR(c.side_cap_mps(c.warning_side_m(v)), v, 1e-9);
  }
  EXPECT_NEAR(c.static_stop_m(1.0), 0.08 + 0.5 + 0.03, 1e-12);
  EXPECT_EQ(c.static_cap_mps(0.02), 0.0);  // inside the margin: no speed fits
}

TEST(SafetyFieldsTest, AStaticObstacleAheadCutsTheSpeedSoItsStopFits) {
  const SafetyFields fields(config(), kBody);
  const SafetyFieldsConfig& c = fields.config();
  // Far: the full speed.
  const ObstacleField far = field_of(box_ahead(5.0));
  FieldVerdict v = fields.check(far, Pose2{}, Twist{1.5, 0.0, 0.0}, 1.5);
  EXPECT_EQ(v.scale, 1.0);
  // 1 m ahead of the bumper: the speed whose stop plus a reaction's travel is 1 m.
  const ObstacleField near = field_of(box_ahead(1.0));
  v = fields.check(near, Pose2{}, Twist{1.5, 0.0, 0.0}, 0.0);
  EXPECT_TRUE(v.static_cut);
  EXPECT_FALSE(v.protective);
  EXPECT_NEAR(v.allowed_mps, c.static_cap_mps(1.0), 0.01);
  EXPECT_NEAR(v.scale * 1.5, v.allowed_mps, 1e-9);
  // Moving at 1.5 m/s with it 1 m ahead: inside the static stop (0.12 + 1.125 + 0.03 m).
  v = fields.check(near, Pose2{}, Twist{1.5, 0.0, 0.0}, 1.5);
  EXPECT_TRUE(v.protective);
  EXPECT_EQ(v.scale, 0.0);
  // Driving away from it: not in the way.
  v = fields.check(near, Pose2{}, Twist{-0.5, 0.0, 0.0}, 0.5);
  EXPECT_EQ(v.scale, 1.0);
  // A turn in place is not the fields' to judge.
  v = fields.check(near, Pose2{}, Twist{0.0, 0.0, 1.0}, 0.0);
  EXPECT_EQ(v.scale, 1.0);
}

TEST(SafetyFieldsTest, AWallBesideTheBandDoesNotSlowTheRobot) {
  const SafetyFields fields(config(), kBody);
  test::ScanScene s;
  const double y = kBody.half_width_m + 0.15;  // a corridor wall 0.15 m from the side
  s.segments.push_back({Vec2(-3.0, y), Vec2(6.0, y)});
  s.segments.push_back({Vec2(-3.0, -y), Vec2(6.0, -y)});
  const FieldVerdict v = fields.check(field_of(s), Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0);
  EXPECT_EQ(v.scale, 1.0);
  EXPECT_FALSE(v.protective);
}

TEST(SafetyFieldsTest, SomethingMovingBesideThePathSlowsTheRobotUntilItsWarningFieldClears) {
  const SafetyFields fields(config(), kBody);
  const SafetyFieldsConfig& c = fields.config();
  test::ScanScene s;
  s.discs.push_back({Vec2(1.5, kBody.half_width_m + 0.8 + 0.2), 0.2});  // 0.8 m beside, 1.25 ahead
  ObstacleField f = field_of(s);
  ASSERT_GT(f.points().size(), 5U);
  // Static, it is beside the band: no cut.
  EXPECT_EQ(fields.check(f, Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0).scale, 1.0);
  // Moving: the robot slows to the speed whose warning field it is outside.
  for (std::size_t i = 0; i < f.points().size(); ++i) f.set_moving(i, true);
  const FieldVerdict v = fields.check(f, Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0);
  EXPECT_TRUE(v.warning);
  EXPECT_FALSE(v.protective);
  EXPECT_LT(v.allowed_mps, 1.0);
  EXPECT_GE(v.allowed_mps, c.side_cap_mps(0.8) - 1e-9);
  // Far beside (3 m): outside the warning field at 1 m/s.
  test::ScanScene far;
  far.discs.push_back({Vec2(1.5, kBody.half_width_m + 3.2), 0.2});
  ObstacleField g = field_of(far);
  for (std::size_t i = 0; i < g.points().size(); ++i) g.set_moving(i, true);
  EXPECT_EQ(fields.check(g, Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0).scale, 1.0);
}

TEST(SafetyFieldsTest, TheFieldsLieInTheDirectionOfTravel) {
  const SafetyFields fields(config(), kBody);
  test::ScanScene s;
  s.segments.push_back({Vec2(-0.3, 0.5), Vec2(0.3, 0.5)});  // 0.3 m to the left of the body
  const ObstacleField f = field_of(s);
  // Strafing left at 0.5 m/s toward it: its static stop is 0.04 + 0.125 + 0.03 = 0.195 m, and
  // that plus a reaction's travel (0.04 m) fits in 0.3 m: neither cut nor stopped; at 0.7 m/s
  // it is cut.
  FieldVerdict v = fields.check(f, Pose2{}, Twist{0.0, 0.5, 0.0}, 0.0);
  EXPECT_EQ(v.scale, 1.0);
  v = fields.check(f, Pose2{}, Twist{0.0, 0.7, 0.0}, 0.0);
  EXPECT_TRUE(v.static_cut);
  EXPECT_LT(v.allowed_mps, 0.7);
  v = fields.check(f, Pose2{}, Twist{0.0, 0.8, 0.0}, 0.8);
  EXPECT_TRUE(v.protective);
  // Strafing right, away from it: free.
  EXPECT_EQ(fields.check(f, Pose2{}, Twist{0.0, -0.8, 0.0}, 0.8).scale, 1.0);
  // Forward: beside the band.
  EXPECT_EQ(fields.check(f, Pose2{}, Twist{0.8, 0.0, 0.0}, 0.8).scale, 1.0);
}

TEST(SafetyFieldsTest, ADirectionTheLidarCannotSeeIsDrivenAtTheBlindSpeed) {
  const SafetyFields fields(config(), kBody);
  test::ScanScene s;
  s.segments.push_back({Vec2(8.0, -5.0), Vec2(8.0, 5.0)});
  const ObstacleField front = field_of(s, 180.0);  // a front lidar: nothing seen behind
  const FieldVerdict back = fields.check(front, Pose2{}, Twist{-0.6, 0.0, 0.0}, 0.6);
  EXPECT_TRUE(back.blind);
  EXPECT_NEAR(back.allowed_mps, fields.config().blind_speed_mps, 1e-12);
  const FieldVerdict ahead = fields.check(front, Pose2{}, Twist{0.6, 0.0, 0.0}, 0.6);
  EXPECT_FALSE(ahead.blind);
  EXPECT_EQ(ahead.scale, 1.0);
}

TEST(SafetyFieldsTest, DisabledOrWithoutAScanTheRequestPassesUnchanged) {
  SafetyFieldsConfig c = config();
  c.enabled = false;
  const ObstacleField near = field_of(box_ahead(0.05));
  EXPECT_EQ(SafetyFields(c, kBody).check(near, Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0).scale, 1.0);
  const ObstacleField none(kBody, 0.0, 0.0, 0.0);
  EXPECT_EQ(SafetyFields(config(), kBody).check(none, Pose2{}, Twist{1.0, 0.0, 0.0}, 1.0).scale,
            1.0);
}

TEST(SafetyFieldsTest, ConfigValidateNamesTheField) {
  SafetyFieldsConfig c = config();
  c.approach_speed_mps = 9.0;
  const Status s = c.validate();
  ASSERT_FALSE(s);
  EXPECT_NE(
      std::string(s.message()).find("runner.fields.approach_speed_mps: 9 m/s, expected 0 to 5 m/s"),
      std::string::npos)
      << s.message();
}

}  // namespace
}  // namespace carril::fw
