// Every numeric range the loader accepts, at each of its corners (the bound itself for a closed
// bound, the nearest accepted value for an open one): the file loads, and one simulated second
// runs without a signal (the test main traps FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW). Each
// corner is its own test case, so a crash fails only that case.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host_sim/app/SimRun.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"

namespace carril::sim {
namespace {

// A preset and a scenario in which every key appears once with a distinct value, so one textual
// replacement sets one key.
const std::string kPreset = R"(name: campero
drive: mecanum
body: {length_m: 0.98, width_m: 0.78, mass_kg: 110.0}
wheels: {radius_m: 0.127, wheelbase_m: 0.60, track_m: 0.61}
cruise_speed_mps: 0.5
control_rate_hz: 100
camera: {x_m: 0.49, y_m: 0.01, z_m: 0.90, tilt_deg: 55.0, hfov_deg: 54.2, width: 640, height: 480, rate_hz: 30, noise_std: 0.0}
lidar: {x_m: 0.45, y_m: -0.35, yaw_deg: -45.0, fov_deg: 270.0, beams: 541, range_min_m: 0.05, range_max_m: 20.0, rate_hz: 20, noise_std_m: 0.01}
limits: {max_speed_mps: 1.5, max_yaw_rate_radps: 1.5, max_accel_mps2: 1.0, max_wheel_speed_radps: 12.0, max_wheel_accel_radps2: 25.0}
traversability: {max_slope_deg: 5.0, max_step_up_m: 0.02, max_step_down_m: 0.05}
terrain_limits: {max_slope_deg: 10.0, max_step_up_m: 0.03, max_step_down_m: 0.08}
)";

const std::string kScenario = R"(name: corner
duration_s: 10
seed: 1
floor: {color: [90, 91, 92]}
robot:
  preset: campero
  start: {x: 0, y: 0.001, yaw_deg: 0}
mission: {type: follow_line, strategy: marks, line_color: white, end_color: yellow, speed_mps: 0.3}
lines:
  - {color: white, width_m: 0.05, points: [[0.002, 0], [3, 0]]}
  - {color: white, width_m: 0.06, arc: {center: [3, 1], radius_m: 1, start_deg: -90, end_deg: 0}}
marks:
  - {color: [255, 255, 0], x: 4, y: 1.003, radius_m: 0.15}
obstacles:
  - {shape: box, x: 6, y: -3, yaw_deg: 30, size_m: [1.01, 1.02]}
  - {shape: cylinder, x: 6.5, y: 3, radius_m: 0.5}
  - {shape: box, x: 7, y: -4.5, size_m: [0.5, 0.5], height_m: 1.13}
walls:
  - {points: [[-5, -5], [8, -5.004]], thickness_m: 0.1}
terrain:
  - {type: ramp, x: -3, y: 3.005, yaw_deg: 10, length_m: 1.03, width_m: 1.04, angle_deg: 5}
  - {type: step, x: -3.5, y: -3, length_m: 1.05, width_m: 1.06, height_m: 0.05}
  - {type: ramp, x: -7, y: 3, length_m: 1.07, width_m: 1.08, angle_deg: 6, angle2_deg: 12, length2_m: 1.09, top_m: 0.4, descend: false}
  - {type: trench, x: -7, y: -3, length_m: 1.11, width_m: 1.12, depth_m: 0.3}
expect: {end_reached: true, max_collisions: 0, max_cross_track_rms_m: 0.05, min_progress: 0.5, min_laps: 0, max_end_stop_error_m: 0.1}
)";

using Edits = std::vector<std::pair<std::string, std::string>>;

struct Corner {
  std::string name;
  Edits preset, scenario;
  // Not empty: the value passes its own check, but the robot as a whole is refused at load with
  // this in the message (a lidar that cannot see as far as the robot needs to stop).
  std::string refused = {};
};

std::ostream& operator<<(std::ostream& os, const Corner& c) {
  return os << c.name;
}

std::string apply(std::string text, const Edits& edits) {
  for (const auto& [from, to] : edits) {
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) text.replace(pos, from.size(), to);
  }
  return text;
}

// A key of the preset (P) or scenario (S) file: the text that holds it (e.g. "z_m: 0.90"), the
// key as replaced ("z_m: "), its two corners, and edits that the corner needs elsewhere to stay
// valid (lo, hi).
struct Range2 {
  char file;
  std::string name, from, key, lo, hi;
  Edits lo_p = {}, lo_s = {}, hi_p = {}, hi_s = {};
  std::string lo_refused = {}, hi_refused = {};
};

std::vector<Corner> corners() {
  const std::string tiny = "4.9406564584124654e-324";  // nextafter(0, 1)
  const std::vector<Range2> ranges = {
      // Preset: body, wheels, rates, speeds.
      {'P', "body_length", "length_m: 0.98", "length_m: ", "0.1", "5"},
      {'P', "body_width", "width_m: 0.78", "width_m: ", "0.1", "5"},
      {'P', "body_mass", "mass_kg: 110.0", "mass_kg: ", "1", "5000"},
      {'P',
       "wheel_radius",
       "radius_m: 0.127",
       "radius_m: ",
       "0.01",
       "1",
       {{"max_wheel_speed_radps: 12.0", "max_wheel_speed_radps: 500"}}},
      {'P', "wheelbase", "wheelbase_m: 0.60", "wheelbase_m: ", "0.05", "5"},
      {'P', "track", "track_m: 0.61", "track_m: ", "0.05", "5"},
      {'P', "control_rate", "control_rate_hz: 100", "control_rate_hz: ", "10", "1000"},
      {'P',
       "cruise_speed",
       "cruise_speed_mps: 0.5",
       "cruise_speed_mps: ",
       "0.01",
       "5",
       {},
       {},
       // 5 m/s needs a warning field of 23 m: a lidar that sees 30 m.
       {{"max_speed_mps: 1.5", "max_speed_mps: 5"}, {"range_max_m: 20.0", "range_max_m: 30.0"}}},
      // Camera.
      {'P', "camera_x", "x_m: 0.49", "x_m: ", "-5", "5"},
      {'P', "camera_y", "y_m: 0.01", "y_m: ", "-5", "5"},
      {'P', "camera_z", "z_m: 0.90", "z_m: ", "0.05", "5"},
      {'P',
       "camera_tilt",
       "tilt_deg: 55.0",
       "tilt_deg: ",
       "5",
       "90",
       {{"hfov_deg: 54.2", "hfov_deg: 20"}, {"height: 480", "height: 32"}}},
      {'P',
       "camera_hfov",
       "hfov_deg: 54.2",
       "hfov_deg: ",
       "20",
       "150",
       {},
       {},
       {{"height: 480", "height: 32"}, {"tilt_deg: 55.0", "tilt_deg: 90"}}},
      {'P', "camera_width", "width: 640", "width: ", "32", "1280", {{"height: 480", "height: 32"}}},
      {'P',
       "camera_height",
       "height: 480",
       "height: ",
       "32",
       "960",
       {},
       {},
       {{"width: 640", "width: 1280"}}},
      {'P', "camera_rate", "rate_hz: 30", "rate_hz: ", "1", "240"},
      {'P', "camera_noise", "noise_std: 0.0", "noise_std: ", "0", "100"},
      // Lidar.
      {'P', "lidar_x", "x_m: 0.45", "x_m: ", "-5", "5"},
      {'P', "lidar_y", "y_m: -0.35", "y_m: ", "-5", "5"},
      {'P', "lidar_yaw", "yaw_deg: -45.0", "yaw_deg: ", "-360", "360"},
      {'P', "lidar_fov", "fov_deg: 270.0", "fov_deg: ", "1", "360"},
      {'P', "lidar_beams", "beams: 541", "beams: ", "2", "2048"},
      {'P', "lidar_range_min", "range_min_m: 0.05", "range_min_m: ", "0", "10"},
      // A 0.5 m lidar sees less than campero's warning field even standing (1.06 m to its far
      // corner from the lidar): refused with the numbers, at any speed.
      {'P', "lidar_range_max", "range_max_m: 20.0", "range_max_m: ", "0.5", "100", {}, {}, {}, {},
       "beyond lidar.reliable_range_m 0.5 m"},
      // range_min_m < range_max_m: the nearest accepted value below the open bound.
      {'P',
       "lidar_range_min_below_max",
       "range_min_m: 0.05",
       "range_min_m: ",
       "0",
       "0.49999999999999994",
       {},
       {},
       {{"range_max_m: 20.0", "range_max_m: 0.5"}},
       {},
       {},
       "beyond lidar.reliable_range_m 0.5 m"},
      {'P', "lidar_rate", "rate_hz: 20", "rate_hz: ", "1", "100"},
      {'P', "lidar_noise", "noise_std_m: 0.01", "noise_std_m: ", "0", "1"},
      // Limits.
      {'P',
       "max_speed",
       "max_speed_mps: 1.5",
       "max_speed_mps: ",
       "0.05",
       "5",
       {{"cruise_speed_mps: 0.5", "cruise_speed_mps: 0.05"}},
       {{"speed_mps: 0.3", "speed_mps: 0.05"}},
       {{"range_max_m: 20.0", "range_max_m: 30.0"}}},
      {'P', "max_yaw_rate", "max_yaw_rate_radps: 1.5", "max_yaw_rate_radps: ", "0.05", "10"},
      // Braking at 0.05 m/s^2 from 1.5 m/s takes 22.5 m: a slow robot (0.3 m/s: 10.8 m).
      {'P', "max_accel", "max_accel_mps2: 1.0", "max_accel_mps2: ", "0.05", "20",
       {{"max_speed_mps: 1.5", "max_speed_mps: 0.3"}, {"cruise_speed_mps: 0.5", "cruise_speed_mps: 0.3"}}},
      {'P',
       "max_wheel_speed",
       "max_wheel_speed_radps: 12.0",
       "max_wheel_speed_radps: ",
       "0.5",
       "500",
       {{"radius_m: 0.127", "radius_m: 1"}}},
      {'P', "max_wheel_accel", "max_wheel_accel_radps2: 25.0", "max_wheel_accel_radps2: ", "0.5",
       "5000"},
      {'P', "trav_max_slope", "max_slope_deg: 5.0", "max_slope_deg: ", "0", "60"},
      {'P', "trav_max_step_up", "max_step_up_m: 0.02", "max_step_up_m: ", "0", "1"},
      {'P', "trav_max_step_down", "max_step_down_m: 0.05", "max_step_down_m: ", "0", "1"},
      // Scenario: top level.
      {'S', "duration", "duration_s: 10", "duration_s: ", "0.1", "86400"},
      {'S', "seed", "seed: 1", "seed: ", "0", "18446744073709551615"},
      {'S', "floor_r", "[90, 91, 92]", "[", "0, 91, 92]", "255, 91, 92]"},
      // A dark floor: [90, 91, 0] x1.15 is yellow enough for the end mark.
      {'S', "floor_b", "[90, 91, 92]", "[", "20, 21, 0]", "90, 91, 255]"},
      {'S', "start_x", "x: 0, y: 0.001", "x: ", "-10000, y: 0.001", "10000, y: 0.001"},
      {'S', "start_y", "y: 0.001", "y: ", "-10000", "10000"},
      {'S', "start_yaw", "yaw_deg: 0}", "yaw_deg: ", "-360}", "360}"},
      {'S', "speed", "speed_mps: 0.3", "speed_mps: ", "0.01", "1.5"},
      // Lines.
      {'S', "line_width", "width_m: 0.05", "width_m: ", "0.005", "0.5"},
      {'S', "line_point_x", "[[0.002, 0]", "[[", "-10000, 0]", "10000, 0]"},
      {'S', "line_point_y", "[3, 0]]", "[3, ", "-10000]]", "10000]]"},
      {'S', "arc_center", "center: [3, 1]", "center: ", "[-10000, -10000]", "[10000, 10000]"},
      {'S', "arc_radius", "radius_m: 1,", "radius_m: ", "0.05,", "100,"},
      {'S', "arc_start", "start_deg: -90, end_deg: 0", "start_deg: ", "-3600, end_deg: -3510",
       "3600, end_deg: 3510"},
      {'S', "arc_end", "start_deg: -90, end_deg: 0", "start_deg: ", "-90, end_deg: -3600",
       "-90, end_deg: 3510"},
      // Marks.
      {'S', "mark_color", "[255, 255, 0]", "[", "0, 0, 0]", "255, 255, 255]"},
      {'S', "mark_x", "x: 4, y: 1.003", "x: ", "-10000, y: 1.003", "10000, y: 1.003"},
      {'S', "mark_y", "y: 1.003", "y: ", "-10000", "10000"},
      {'S', "mark_radius", "radius_m: 0.15", "radius_m: ", "0.01", "2"},
      // Obstacles.
      {'S', "box_x", "x: 6, y: -3", "x: ", "-10000, y: -3", "10000, y: -3"},
      {'S', "box_yaw", "yaw_deg: 30", "yaw_deg: ", "-360", "360"},
      {'S',
       "box_size_x",
       "size_m: [1.01, 1.02]",
       "size_m: [",
       "0.01, 1.02]",
       "100, 1.02]",
       {},
       {},
       {},
       {{"x: 6, y: -3", "x: 6, y: -60"}}},
      {'S',
       "box_size_y",
       "size_m: [1.01, 1.02]",
       "size_m: [1.01, ",
       "0.01]",
       "100]",
       {},
       {},
       {},
       {{"x: 6, y: -3", "x: 6, y: -60"}}},
      {'S', "cylinder_y", "x: 6.5, y: 3", "x: 6.5, y: ", "-10000", "10000"},
      {'S',
       "cylinder_radius",
       "radius_m: 0.5",
       "radius_m: ",
       "0.01",
       "50",
       {},
       {},
       {},
       {{"x: 6.5, y: 3", "x: 6.5, y: 60"}}},
      // Walls.
      {'S', "wall_point", "[8, -5.004]", "[8, ", "-10000]", "10000]"},
      {'S',
       "wall_thickness",
       "thickness_m: 0.1",
       "thickness_m: ",
       "0.01",
       "10",
       {},
       {},
       {},
       {{"[[-5, -5], [8, -5.004]]", "[[-5, -50], [8, -50]]"}}},
      // Terrain.
      {'S', "terrain_x", "x: -3, y: 3.005", "x: ", "-10000, y: 3.005", "10000, y: 3.005"},
      {'S', "terrain_yaw", "yaw_deg: 10", "yaw_deg: ", "-360", "360"},
      {'S',
       "terrain_length",
       "length_m: 1.03",
       "length_m: ",
       "0.01",
       "100",
       {},
       {},
       {},
       {{"x: -3, y: 3.005", "x: -3, y: 300"}}},
      {'S',
       "terrain_width",
       "width_m: 1.06",
       "width_m: ",
       "0.01",
       "100",
       {},
       {},
       {},
       {{"x: -3.5, y: -3", "x: -3.5, y: -300"}}},
      {'S', "ramp_angle", "angle_deg: 5", "angle_deg: ", "0.5", "30"},
      {'S', "step_height", "height_m: 0.05", "height_m: ", "0.005", "0.5"},
      {'S', "pit_depth", "height_m: 0.05", "height_m: ", "-0.5", "-0.005"},
      {'S', "ramp2_angle", "angle2_deg: 12", "angle2_deg: ", "0.5", "30"},
      {'S',
       "ramp2_length",
       "length2_m: 1.09",
       "length2_m: ",
       "0.01",
       "100",
       {},
       {},
       {},
       {{"x: -7, y: 3", "x: -7, y: 400"}}},
      {'S',
       "ramp_top",
       "top_m: 0.4",
       "top_m: ",
       "0",
       "100",
       {},
       {},
       {},
       {{"x: -7, y: 3", "x: -7, y: 400"}}},
      {'S', "trench_depth", "depth_m: 0.3", "depth_m: ", "0.005", "1"},
      {'S', "obstacle_height", "height_m: 1.13", "height_m: ", "0.01", "10"},
      {'P', "terrain_max_slope", "max_slope_deg: 10.0", "max_slope_deg: ", "1", "60"},
      {'P', "terrain_max_step_up", "max_step_up_m: 0.03", "max_step_up_m: ", "0.005", "1"},
      {'P', "terrain_max_step_down", "max_step_down_m: 0.08", "max_step_down_m: ", "0.005", "2"},
      // Expect.
      {'S', "max_collisions", "max_collisions: 0", "max_collisions: ", "0", "1000000"},
      {'S', "cross_track", "max_cross_track_rms_m: 0.05", "max_cross_track_rms_m: ", tiny, "10"},
      {'S', "min_progress", "min_progress: 0.5", "min_progress: ", "0", "1"},
      {'S', "min_laps", "min_laps: 0", "min_laps: ", "0", "1000000"},
      {'S', "end_stop_error", "max_end_stop_error_m: 0.1", "max_end_stop_error_m: ", tiny, "10"},
  };
  std::vector<Corner> out;
  for (const Range2& r : ranges) {
    for (const bool hi : {false, true}) {
      Corner c;
      c.name = r.name + (hi ? "_hi" : "_lo");
      Edits& own = r.file == 'P' ? c.preset : c.scenario;
      own.emplace_back(r.from, r.key + (hi ? r.hi : r.lo));
      for (const auto& e : hi ? r.hi_p : r.lo_p) c.preset.push_back(e);
      for (const auto& e : hi ? r.hi_s : r.lo_s) c.scenario.push_back(e);
      c.refused = hi ? r.hi_refused : r.lo_refused;
      out.push_back(std::move(c));
    }
  }
  return out;
}

class CornerValues : public ::testing::TestWithParam<Corner> {};

TEST_P(CornerValues, LoadsAndRunsOneSecond) {
  const Corner& c = GetParam();
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / ("carril_corner_" + c.name);
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "campero.yaml") << apply(kPreset, c.preset); }
  const std::string path = (dir / "corner.yaml").string();
  { std::ofstream(path) << apply(kScenario, c.scenario); }
  LoadResult r = load_scenario(path, dir.string());
  ASSERT_TRUE(r.ok) << r.error;
  if (!c.refused.empty()) {
    // The firmware's configuration is checked as a whole when the run is built, before any tick.
    try {
      SimRun refused(r.scenario, r.scenario.seed);
      ADD_FAILURE() << "accepted; expected a refusal with: " << c.refused;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.refused), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
    return;
  }
  r.scenario.duration_s = 1.0;
  SimRun run(r.scenario, r.scenario.seed);
  while (run.step()) {
  }
  EXPECT_GE(run.sim_time_s(), 0.99);
  const RunSummary s = run.summary(1.0);
  EXPECT_FALSE(s.result.empty());
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Scenario, CornerValues, ::testing::ValuesIn(corners()),
                         [](const ::testing::TestParamInfo<Corner>& i) { return i.param.name; });

}  // namespace
}  // namespace carril::sim
