// The robot description's `traversability:` section: the shipped figures, and a strict message
// naming the file, line and key for each kind of error.
#include <gtest/gtest.h>

#include <algorithm>

#include "loader/RobotLoader.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::edit;
using test::read_text;
using test::source_path;
using test::write_file;

const std::string kCampero = read_text(source_path("config/robots/campero.yaml"));
const std::string kSection =
    "traversability: {max_slope_deg: 5.0, max_step_up_m: 0.02, max_step_down_m: 0.05}";

// "<file>:<line>: " of the campero file's traversability line.
std::string line_of_section(const std::string& path) {
  const auto pos = kCampero.find(kSection);
  EXPECT_NE(pos, std::string::npos);
  const auto line = std::count(kCampero.begin(), kCampero.begin() + static_cast<long>(pos), '\n');
  return path + ":" + std::to_string(line + 1) + ": ";
}

struct Loaded {
  bool ok = false;
  RobotSpec robot;
  std::string error;
  std::string path;
};

Loaded load(const std::string& text) {
  Loaded l;
  l.path = write_file("traversability_robot.yaml", text);
  l.ok = load_robot_preset(l.path, l.robot, l.error);
  return l;
}

TEST(RobotTraversability, ShippedRobotsCarryTheirFigures) {
  const RobotSpec pioneer = test::robot("pioneer3at");
  EXPECT_DOUBLE_EQ(pioneer.traversability.max_slope_deg, 8.0);
  EXPECT_DOUBLE_EQ(pioneer.traversability.max_step_up_m, 0.03);
  EXPECT_DOUBLE_EQ(pioneer.traversability.max_step_down_m, 0.10);
  const RobotSpec campero = test::robot("campero");
  EXPECT_DOUBLE_EQ(campero.traversability.max_slope_deg, 5.0);
  EXPECT_DOUBLE_EQ(campero.traversability.max_step_up_m, 0.02);
  EXPECT_DOUBLE_EQ(campero.traversability.max_step_down_m, 0.05);
}

TEST(RobotTraversability, MissingSectionOrKeyIsNamed) {
  const Loaded section = load(edit(kCampero, kSection + "\n", ""));
  ASSERT_FALSE(section.ok);
  // Reported at the top-level map's line, like every missing top-level key.
  EXPECT_EQ(section.error.rfind(section.path + ":", 0), 0U) << section.error;
  EXPECT_NE(section.error.find(": traversability: missing required key"), std::string::npos)
      << section.error;
  const Loaded key = load(edit(kCampero, ", max_step_down_m: 0.05", ""));
  ASSERT_FALSE(key.ok);
  EXPECT_EQ(key.error,
            line_of_section(key.path) + "traversability.max_step_down_m: missing required key");
}

TEST(RobotTraversability, NegativeValueIsRejected) {
  const Loaded l = load(edit(kCampero, "max_step_up_m: 0.02", "max_step_up_m: -0.02"));
  ASSERT_FALSE(l.ok);
  EXPECT_EQ(l.error, line_of_section(l.path) +
                         "traversability.max_step_up_m: expected a number in [0, 1], got -0.02");
}

TEST(RobotTraversability, OutOfRangeValueIsRejected) {
  const Loaded slope = load(edit(kCampero, "max_slope_deg: 5.0", "max_slope_deg: 75"));
  ASSERT_FALSE(slope.ok);
  EXPECT_EQ(slope.error, line_of_section(slope.path) +
                             "traversability.max_slope_deg: expected a number in [0, 60], got 75");
  const Loaded down = load(edit(kCampero, "max_step_down_m: 0.05", "max_step_down_m: 1.5"));
  ASSERT_FALSE(down.ok);
  EXPECT_EQ(down.error, line_of_section(down.path) +
                            "traversability.max_step_down_m: expected a number in [0, 1], got 1.5");
}

TEST(RobotTraversability, UnknownKeyIsRejected) {
  const Loaded l = load(edit(kCampero, "max_step_down_m: 0.05", "max_step_down_m: 0.05, roll: 3"));
  ASSERT_FALSE(l.ok);
  EXPECT_EQ(l.error, line_of_section(l.path) +
                         "traversability.roll: unknown key (allowed: max_slope_deg, max_step_up_m, "
                         "max_step_down_m)");
}

}  // namespace
}  // namespace carril::loader
