#include "host_sim/scenario/ScenarioLoader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "host_sim/scenario/ScenarioChecks.hpp"
#include "host_sim/scenario/StrictYaml.hpp"

#ifndef CARRIL_SOURCE_DIR
#define CARRIL_SOURCE_DIR "."
#endif

namespace carril::sim {

namespace {

using strict::LoadError;
using strict::Node;
using strict::Range;

// Physical bounds: every accepted value gives a finite, non-degenerate simulation (no inf/NaN in
// geometry, rendering or physics, no Box2D assertion). docs/scenario-format.md lists them all.
const Range kCoord = Range::closed(-1.0e4, 1.0e4);  // world coordinates [m]
const Range kYawDeg = Range::closed(-360.0, 360.0);
const Range kMount = Range::closed(-5.0, 5.0);      // sensor mount offsets [m]
const Range kSize = Range::closed(0.01, 100.0);     // obstacle and terrain sizes [m]
const Range kWheelSize = Range::closed(0.05, 5.0);  // wheelbase, track [m]

constexpr double kArcStepM = 0.02;  // max spacing of discretised arc points [m]
constexpr double kMaxArcSweepDeg = 3600.0;
constexpr std::size_t kMaxNameLength = 64;

// Derived camera rules: the top image row looks at least this far below the horizon, and the
// optical axis meets the floor within this distance.
constexpr double kMinTopRowDepressionDeg = 1.0;
constexpr double kMaxCentreRayDistanceM = 20.0;

// Tape geometry: a line at least this long; consecutive points at least this far apart.
constexpr double kMinLineLengthM = 0.01;
constexpr double kMinSegmentM = 0.001;

// Size limits, checked before anything is expanded or iterated (YAML aliases make a small file
// into a huge tree). Generous for a real factory floor.
constexpr std::size_t kMaxTapePoints = 20000;  // all lines, after arc discretisation
constexpr std::size_t kMaxLines = 256;
constexpr std::size_t kMaxMarks = 64;
constexpr std::size_t kMaxObstacles = 256;
constexpr std::size_t kMaxWalls = 256;
constexpr std::size_t kMaxWallPoints = 4096;  // all walls
constexpr std::size_t kMaxTerrain = 256;

double deg2rad(double deg) {
  return deg * std::numbers::pi / 180.0;
}

bool valid_name(const std::string& s) {
  if (s.empty() || s.size() > kMaxNameLength) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

std::string parse_name(const Node& n) {
  const std::string s = n.string();
  if (!valid_name(s)) n.expected("a name of 1 to 64 letters, digits, '_' or '-'");
  return s;
}

// ---- Shared value types ----

Rgb parse_color(const Node& n, std::string* name_out = nullptr) {
  const std::string what = "a colour name (white, black, red, green, blue, yellow) or [r, g, b]";
  if (n.yaml().IsSequence()) {
    const auto c = n.items();
    if (c.size() != 3) n.expected(what, "a list of " + std::to_string(c.size()));
    const Rgb rgb{static_cast<std::uint8_t>(c[0].integer(0, 255)),
                  static_cast<std::uint8_t>(c[1].integer(0, 255)),
                  static_cast<std::uint8_t>(c[2].integer(0, 255))};
    if (name_out) {
      *name_out = "[" + std::to_string(rgb.r) + ", " + std::to_string(rgb.g) + ", " +
                  std::to_string(rgb.b) + "]";
    }
    return rgb;
  }
  Rgb rgb;
  if (!n.yaml().IsScalar() || !color_from_name(n.string(), rgb)) n.expected(what);
  if (name_out) *name_out = n.string();
  return rgb;
}

Vec2 parse_point(const Node& n) {
  const auto xy = n.items();
  if (xy.size() != 2) n.expected("[x, y] (2 numbers)", "a list of " + std::to_string(xy.size()));
  return {xy[0].number(kCoord), xy[1].number(kCoord)};
}

// A list of at least 2 points, of which there may be no more than `budget` (what is left of a
// total limit, described by `limit_what`); the size is checked before any item is read.
std::vector<Vec2> parse_points(const Node& n, std::size_t& budget, const std::string& limit_what) {
  if (!n.yaml().IsSequence()) n.expected("a list");
  if (n.yaml().size() > budget) {
    n.expected(limit_what,
               std::to_string(n.yaml().size()) + " more, with " + std::to_string(budget) + " left");
  }
  std::vector<Vec2> out;
  for (const Node& p : n.items(2)) out.push_back(parse_point(p));
  budget -= out.size();
  return out;
}

// ---- Robot preset blocks; `all` = every key required (preset file) or optional (override) ----

void parse_camera(const Node& m, CameraSpec& c, bool all) {
  m.expect_map(
      {"x_m", "y_m", "z_m", "tilt_deg", "hfov_deg", "width", "height", "rate_hz", "noise_std"});
  if (auto n = m.get("x_m", all)) c.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) c.y_m = n->number(kMount);
  if (auto n = m.get("z_m", all)) c.z_m = n->number(Range::closed(0.05, 5.0));
  if (auto n = m.get("tilt_deg", all)) c.tilt_deg = n->number(Range::closed(5.0, 90.0));
  if (auto n = m.get("hfov_deg", all)) c.hfov_deg = n->number(Range::closed(20.0, 150.0));
  // The firmware's image buffer is fixed at hal::kMaxImageWidth x kMaxImageHeight.
  if (auto n = m.get("width", all)) c.width = static_cast<int>(n->integer(32, 1280));
  if (auto n = m.get("height", all)) c.height = static_cast<int>(n->integer(32, 960));
  if (auto n = m.get("rate_hz", all)) c.rate_hz = n->number(Range::closed(1.0, 240.0));
  if (auto n = m.get("noise_std", all)) c.noise_std = n->number(Range::closed(0.0, 100.0));
}

// The camera must see the floor: the top image row looks below the horizon (else part of the
// image has no floor and the homography's inverse degenerates) and the image centre meets the
// floor at a sane distance. `where` is the camera block that set the values.
void check_camera_view(const Node& where, const CameraSpec& c) {
  const double half_vfov_deg =
      std::atan((c.height / 2.0) / ((c.width / 2.0) / std::tan(deg2rad(c.hfov_deg / 2.0)))) *
      180.0 / std::numbers::pi;
  const double top_row_deg = c.tilt_deg - half_vfov_deg;
  if (top_row_deg < kMinTopRowDepressionDeg) {
    where.child_path("tilt_deg")
        .expected("a tilt at least " + strict::format_number(kMinTopRowDepressionDeg) +
                      " deg more than half the vertical field of view (" +
                      strict::format_number(half_vfov_deg) + " deg from hfov_deg " +
                      strict::format_number(c.hfov_deg) + ", " + std::to_string(c.width) + "x" +
                      std::to_string(c.height) + "), so the whole image sees the floor",
                  strict::format_number(c.tilt_deg));
  }
  const double centre_m = c.z_m / std::tan(deg2rad(c.tilt_deg));
  if (centre_m > kMaxCentreRayDistanceM) {
    where.child_path("tilt_deg")
        .expected("a tilt whose image centre meets the floor within " +
                      strict::format_number(kMaxCentreRayDistanceM) + " m (z_m " +
                      strict::format_number(c.z_m) +
                      " / tan(tilt_deg) = " + strict::format_number(centre_m) + " m)",
                  strict::format_number(c.tilt_deg));
  }
}

void parse_lidar(const Node& m, LidarSpec& l, bool all) {
  m.expect_map({"x_m", "y_m", "yaw_deg", "fov_deg", "beams", "range_min_m", "range_max_m",
                "rate_hz", "noise_std_m"});
  if (auto n = m.get("x_m", all)) l.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) l.y_m = n->number(kMount);
  if (auto n = m.get("yaw_deg", all)) l.yaw_deg = n->number(kYawDeg);
  if (auto n = m.get("fov_deg", all)) l.fov_deg = n->number(Range::closed(1.0, 360.0));
  // hal::kMaxScanBeams.
  if (auto n = m.get("beams", all)) l.beams = static_cast<int>(n->integer(2, 2048));
  const auto max_n = m.get("range_max_m", all);
  const auto min_n = m.get("range_min_m", all);
  if (max_n) l.range_max_m = max_n->number(Range::closed(0.5, 100.0));
  if (min_n) {
    l.range_min_m = min_n->number(Range::closed(0.0, 10.0));
    if (l.range_min_m >= l.range_max_m) {
      min_n->expected("a number in [0, range_max_m = " + strict::format_number(l.range_max_m) + ")",
                      min_n->raw());
    }
  } else if (max_n && l.range_max_m <= l.range_min_m) {
    max_n->expected("a number in (range_min_m = " + strict::format_number(l.range_min_m) + ", 100]",
                    max_n->raw());
  }
  if (auto n = m.get("rate_hz", all)) l.rate_hz = n->number(Range::closed(1.0, 100.0));
  if (auto n = m.get("noise_std_m", all)) l.noise_std_m = n->number(Range::closed(0.0, 1.0));
}

void parse_limits(const Node& m, LimitsSpec& l, bool all) {
  m.expect_map({"max_speed_mps", "max_yaw_rate_radps", "max_accel_mps2", "max_wheel_speed_radps",
                "max_wheel_accel_radps2"});
  auto get = [&](const char* key, double lo, double hi, double& out) {
    if (auto n = m.get(key, all)) out = n->number(Range::closed(lo, hi));
  };
  get("max_speed_mps", 0.05, 5.0, l.max_speed_mps);
  get("max_yaw_rate_radps", 0.05, 10.0, l.max_yaw_rate_radps);
  get("max_accel_mps2", 0.05, 20.0, l.max_accel_mps2);
  get("max_wheel_speed_radps", 0.5, 500.0, l.max_wheel_speed_radps);
  get("max_wheel_accel_radps2", 0.5, 5000.0, l.max_wheel_accel_radps2);
}

RobotSpec parse_preset(const Node& root) {
  root.expect_map({"name", "drive", "body", "wheels", "cruise_speed_mps", "control_rate_hz",
                   "camera", "lidar", "limits"});
  RobotSpec r;
  r.preset = parse_name(root.at("name"));
  r.drive = root.at("drive").one_of({"mecanum", "differential"}) == "mecanum"
                ? DriveType::Mecanum
                : DriveType::Differential;
  const Node body = root.at("body");
  body.expect_map({"length_m", "width_m", "mass_kg"});
  r.length_m = body.at("length_m").number(Range::closed(0.1, 5.0));
  r.width_m = body.at("width_m").number(Range::closed(0.1, 5.0));
  r.mass_kg = body.at("mass_kg").number(Range::closed(1.0, 5000.0));
  const Node wheels = root.at("wheels");
  wheels.expect_map({"radius_m", "wheelbase_m", "track_m"});
  r.wheel_radius_m = wheels.at("radius_m").number(Range::closed(0.01, 1.0));
  r.wheelbase_m = wheels.at("wheelbase_m").number(kWheelSize);
  r.track_m = wheels.at("track_m").number(kWheelSize);
  r.control_rate_hz = root.at("control_rate_hz").number(Range::closed(10.0, 1000.0));
  const Node camera = root.at("camera");
  parse_camera(camera, r.camera, true);
  check_camera_view(camera, r.camera);
  parse_lidar(root.at("lidar"), r.lidar, true);
  parse_limits(root.at("limits"), r.limits, true);
  const Node cruise = root.at("cruise_speed_mps");
  r.cruise_speed_mps = cruise.number(Range::closed(0.01, 5.0));
  if (r.cruise_speed_mps > r.limits.max_speed_mps) {
    cruise.expected("a number in (0, limits.max_speed_mps = " +
                        strict::format_number(r.limits.max_speed_mps) + "]",
                    cruise.raw());
  }
  return r;
}

// The fastest the wheels can carry the body: wheel radius x wheel speed limit.
double wheel_speed_limit_mps(const RobotSpec& r) {
  return r.wheel_radius_m * r.limits.max_wheel_speed_radps;
}

RobotSpec read_preset_file(const std::string& path) {
  const std::string text = strict::read_file(path);
  return parse_preset(strict::parse_document(text, &path));
}

// ---- Scenario sections ----

void parse_robot(const Node& m, const std::string& robots_dir, RobotSpec& robot) {
  m.expect_map({"preset", "start", "camera", "lidar", "limits"});
  const Node preset = m.at("preset");
  const std::string name = preset.one_of({"campero", "pioneer3at"});
  const std::string file = robots_dir + "/" + name + ".yaml";
  try {
    robot = read_preset_file(file);
  } catch (const LoadError& e) {
    preset.fail(std::string("cannot load robot preset: ") + e.what());
  }
  if (robot.preset != name) {
    preset.expected(file + " to declare name: " + name, "name: " + robot.preset);
  }
  if (auto s = m.get("start")) {
    s->expect_map({"x", "y", "yaw_deg"});
    robot.start = {s->at("x").number(kCoord), s->at("y").number(kCoord),
                   deg2rad(s->at("yaw_deg").number(kYawDeg))};
  }
  // Overrides: same schema and checks as the preset, every key optional.
  if (auto n = m.get("camera")) {
    parse_camera(*n, robot.camera, false);
    check_camera_view(*n, robot.camera);
  }
  if (auto n = m.get("lidar")) parse_lidar(*n, robot.lidar, false);
  if (auto n = m.get("limits")) parse_limits(*n, robot.limits, false);
}

void parse_mission(const Node& m, const RobotSpec& robot, MissionSpec& mission) {
  m.expect_map({"type", "strategy", "line_color", "end_color", "speed_mps"});
  const Node type = m.at("type");
  if (type.yaml().IsScalar() && (type.string() == "goto" || type.string() == "coverage")) {
    type.expected("follow_line (" + type.string() + " is not supported yet)");
  }
  mission.type = type.one_of({"follow_line"});
  const Node strategy = m.at("strategy");
  mission.strategy = strategy.one_of({"line_priority", "marks", "pid"});
  if (mission.strategy == "line_priority" && robot.drive != DriveType::Mecanum) {
    strategy.expected("marks or pid (line_priority needs a mecanum drive; preset " + robot.preset +
                      " is differential)");
  }
  mission.line_color = parse_color(m.at("line_color"), &mission.line_color_name);
  if (auto n = m.get("end_color")) {
    mission.end_color = parse_color(*n, &mission.end_color_name);
  } else {
    mission.end_color = Rgb{255, 255, 0};
    mission.end_color_name = "yellow";
  }
  const double max_speed = robot.limits.max_speed_mps;
  const std::string speed_range =
      "a number in (0, robot.limits.max_speed_mps = " + strict::format_number(max_speed) + "]";
  std::optional<Node> speed_node = m.get("speed_mps");
  if (speed_node) {
    mission.speed_mps = speed_node->number(Range::closed(0.01, 5.0));
    if (mission.speed_mps > max_speed) speed_node->expected(speed_range, speed_node->raw());
  } else {
    // The preset's cruise speed is only a default: an override lowering the limit below it
    // needs an explicit speed rather than a silent clamp.
    if (robot.cruise_speed_mps > max_speed) {
      m.child_path("speed_mps")
          .expected(speed_range + " (the preset's cruise_speed_mps " +
                        strict::format_number(robot.cruise_speed_mps) + " is above the limit)",
                    "nothing");
    }
    mission.speed_mps = robot.cruise_speed_mps;
  }
  // The wheels must be able to reach the mission speed.
  const double wheel_max = wheel_speed_limit_mps(robot);
  if (mission.speed_mps > wheel_max) {
    const Node where = speed_node ? *speed_node : m.child_path("speed_mps");
    where.expected("a speed the wheels can reach, at most wheels.radius_m " +
                       strict::format_number(robot.wheel_radius_m) +
                       " x limits.max_wheel_speed_radps " +
                       strict::format_number(robot.limits.max_wheel_speed_radps) + " = " +
                       strict::format_number(wheel_max) + " m/s",
                   speed_node ? speed_node->raw()
                              : strict::format_number(mission.speed_mps) + " (the preset's)");
  }
}

std::vector<Vec2> discretise_arc(Vec2 c, double r, double start_deg, double end_deg) {
  const double a0 = deg2rad(start_deg);
  const double a1 = deg2rad(end_deg);
  const double sweep = a1 - a0;  // sign gives the direction: + counter-clockwise
  const auto n = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(std::abs(sweep) * r / kArcStepM)));
  std::vector<Vec2> pts;
  pts.reserve(n + 1);
  for (std::size_t i = 0; i <= n; ++i) {
    // The last point uses end_deg itself so the endpoint is exact, not a rounded sum.
    const double a = i == n ? a1 : a0 + sweep * static_cast<double>(i) / static_cast<double>(n);
    pts.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  return pts;
}

const std::string kTapeLimit =
    "at most " + std::to_string(kMaxTapePoints) + " tape points in all lines (the limit)";

// Total length of a polyline.
double polyline_length(const std::vector<Vec2>& pts) {
  double len = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    len += std::hypot(pts[i + 1].x - pts[i].x, pts[i + 1].y - pts[i].y);
  }
  return len;
}

// `budget`: tape points still allowed in this file.
LineSpec parse_line(const Node& m, std::size_t& budget) {
  m.expect_map({"color", "width_m", "points", "arc"});
  LineSpec line;
  line.color = parse_color(m.at("color"));
  if (auto n = m.get("width_m")) line.width_m = n->number(Range::closed(0.005, 0.5));
  const auto points = m.get("points");
  const auto arc = m.get("arc");
  if (points && arc) m.expected("exactly one of points or arc", "both");
  if (!points && !arc) m.expected("exactly one of points or arc", "neither");
  if (points) {
    line.points = parse_points(*points, budget, kTapeLimit);
    const auto items = points->items();
    for (std::size_t i = 0; i + 1 < line.points.size(); ++i) {
      const Vec2 a = line.points[i], b = line.points[i + 1];
      const double d = std::hypot(b.x - a.x, b.y - a.y);
      if (d < kMinSegmentM) {
        items[i + 1].expected(
            "a point at least 1 mm from the previous one (a zero-length tape "
            "segment), " +
                strict::format_number(d) + " m away",
            "[" + strict::format_number(b.x) + ", " + strict::format_number(b.y) + "]");
      }
    }
    const double len = polyline_length(line.points);
    if (len < kMinLineLengthM) {
      points->expected("a tape at least 0.01 m long", strict::format_number(len) + " m");
    }
    return line;
  }
  arc->expect_map({"center", "radius_m", "start_deg", "end_deg"});
  const Vec2 center = parse_point(arc->at("center"));
  const double radius = arc->at("radius_m").number(Range::closed(0.05, 100.0));
  const double start = arc->at("start_deg").number(Range::closed(-3600.0, 3600.0));
  const Node end_n = arc->at("end_deg");
  const double end = end_n.number(Range::closed(-3600.0, 3600.0));
  const double sweep = std::abs(end - start);
  if (sweep == 0.0 || sweep > kMaxArcSweepDeg) {
    end_n.expected("a number != start_deg and within 3600 of it (start_deg = " +
                       strict::format_number(start) + ")",
                   end_n.raw());
  }
  const double arc_len = deg2rad(sweep) * radius;
  if (arc_len < kMinLineLengthM) {
    end_n.expected("an arc at least 0.01 m long (radius_m x |end_deg - start_deg|)",
                   strict::format_number(arc_len) + " m");
  }
  // The point count is known before discretising: refuse it first.
  const double n_points = std::ceil(arc_len / kArcStepM) + 1.0;
  if (n_points > static_cast<double>(budget)) {
    arc->expected(kTapeLimit, strict::format_number(n_points) + " more for this arc, with " +
                                  std::to_string(budget) + " left");
  }
  line.points = discretise_arc(center, radius, start, end);
  budget -= line.points.size();
  line.from_arc = true;
  return line;
}

MarkSpec parse_mark(const Node& m) {
  m.expect_map({"color", "x", "y", "radius_m"});
  MarkSpec mark;
  mark.color = parse_color(m.at("color"));
  mark.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  if (auto n = m.get("radius_m")) mark.radius_m = n->number(Range::closed(0.01, 2.0));
  return mark;
}

ObstacleSpec parse_obstacle(const Node& m) {
  ObstacleSpec o;
  // The shape decides which keys are allowed, so it is read before the key check.
  const std::string shape = m.at("shape").one_of({"box", "cylinder"});
  if (shape == "box") {
    m.expect_map({"shape", "x", "y", "yaw_deg", "size_m"});
    o.shape = ObstacleShape::Box;
    const Node size = m.at("size_m");
    const auto s = size.items();
    if (s.size() != 2) {
      size.expected("[size_x, size_y] (2 numbers)", "a list of " + std::to_string(s.size()));
    }
    o.size_x_m = s[0].number(kSize);
    o.size_y_m = s[1].number(kSize);
    if (auto n = m.get("yaw_deg")) o.yaw_rad = deg2rad(n->number(kYawDeg));
  } else {
    m.expect_map({"shape", "x", "y", "radius_m"});
    o.shape = ObstacleShape::Cylinder;
    o.radius_m = m.at("radius_m").number(Range::closed(0.01, 50.0));
  }
  o.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  return o;
}

const std::string kWallPointLimit =
    "at most " + std::to_string(kMaxWallPoints) + " wall points in all walls (the limit)";

WallSpec parse_wall(const Node& m, std::size_t& budget) {
  m.expect_map({"points", "thickness_m"});
  WallSpec w;
  w.points = parse_points(m.at("points"), budget, kWallPointLimit);
  if (auto n = m.get("thickness_m")) w.thickness_m = n->number(Range::closed(0.01, 10.0));
  return w;
}

TerrainSpec parse_terrain(const Node& m) {
  TerrainSpec t;
  const std::string type = m.at("type").one_of({"ramp", "step"});
  if (type == "ramp") {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "angle_deg"});
    t.type = TerrainType::Ramp;
    t.angle_deg = m.at("angle_deg").number(Range::closed(0.5, 30.0));
  } else {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "height_m"});
    t.type = TerrainType::Step;
    t.height_m = m.at("height_m").number(Range::closed(0.005, 0.5));
  }
  t.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  if (auto n = m.get("yaw_deg")) t.yaw_rad = deg2rad(n->number(kYawDeg));
  t.length_m = m.at("length_m").number(kSize);
  t.width_m = m.at("width_m").number(kSize);
  return t;
}

ExpectSpec parse_expect(const Node& m) {
  m.expect_map({"end_reached", "max_collisions", "max_cross_track_rms_m", "min_progress",
                "min_laps", "max_end_stop_error_m"});
  ExpectSpec e;
  if (auto n = m.get("end_reached")) e.end_reached = n->boolean();
  if (auto n = m.get("max_collisions")) e.max_collisions = static_cast<int>(n->integer(0, 1000000));
  if (auto n = m.get("max_cross_track_rms_m")) {
    e.max_cross_track_rms_m = n->number(Range::open_closed(0.0, 10.0));
  }
  if (auto n = m.get("min_progress")) e.min_progress = n->number(Range::closed(0.0, 1.0));
  if (auto n = m.get("min_laps")) e.min_laps = static_cast<int>(n->integer(0, 1000000));
  if (auto n = m.get("max_end_stop_error_m")) {
    e.max_end_stop_error_m = n->number(Range::open_closed(0.0, 10.0));
  }
  return e;
}

// A list of at most `max_items` (checked before any item is read), each read by parse_item.
template <typename T, typename F>
std::vector<T> parse_list(const std::optional<Node>& n, std::size_t max_items, const char* what,
                          F parse_item) {
  std::vector<T> out;
  if (!n) return out;
  if (!n->yaml().IsSequence()) n->expected("a list");
  if (n->yaml().size() > max_items) {
    n->expected("at most " + std::to_string(max_items) + " " + what + " (the limit)",
                "a list of " + std::to_string(n->yaml().size()));
  }
  for (const Node& item : n->items()) out.push_back(parse_item(item));
  return out;
}

Scenario parse_scenario(const Node& root, const std::string& path, const std::string& robots_dir) {
  root.expect_map({"name", "description", "duration_s", "seed", "floor", "robot", "mission",
                   "lines", "marks", "obstacles", "walls", "terrain", "expect"});
  Scenario s;
  s.source_path = path;
  s.name = parse_name(root.at("name"));
  if (auto n = root.get("description")) s.description = n->string();
  s.duration_s = root.at("duration_s").number(Range::closed(0.1, 86400.0));
  if (auto n = root.get("seed")) s.seed = n->unsigned_integer();
  if (auto n = root.get("floor")) {
    n->expect_map({"color"});
    s.floor = parse_color(n->at("color"));
  }
  parse_robot(root.at("robot"), robots_dir, s.robot);
  parse_mission(root.at("mission"), s.robot, s.mission);
  const auto lines = root.get("lines");
  std::size_t tape_budget = kMaxTapePoints;
  s.lines = parse_list<LineSpec>(lines, kMaxLines, "lines",
                                 [&](const Node& n) { return parse_line(n, tape_budget); });
  s.marks = parse_list<MarkSpec>(root.get("marks"), kMaxMarks, "marks", parse_mark);
  s.obstacles =
      parse_list<ObstacleSpec>(root.get("obstacles"), kMaxObstacles, "obstacles", parse_obstacle);
  std::size_t wall_budget = kMaxWallPoints;
  s.walls = parse_list<WallSpec>(root.get("walls"), kMaxWalls, "walls",
                                 [&](const Node& n) { return parse_wall(n, wall_budget); });
  s.terrain =
      parse_list<TerrainSpec>(root.get("terrain"), kMaxTerrain, "terrain items", parse_terrain);
  if (auto n = root.get("expect")) s.expect = parse_expect(*n);

  // follow_line needs tape of the mission's colour to follow.
  const bool has_line = std::any_of(s.lines.begin(), s.lines.end(), [&](const LineSpec& l) {
    return l.color == s.mission.line_color;
  });
  if (!has_line) {
    const Node where = lines ? *lines : Node(YAML::Node(), "lines", &path);
    where.expected("at least one line of mission.line_color " + s.mission.line_color_name,
                   !lines            ? "no lines"
                   : s.lines.empty() ? "an empty list"
                                     : "no line of that colour");
  }
  check_colours(root, s);
  check_start_clear(root, s);
  return s;
}

// Writes `value` (when not empty) as the scalar at root.section.key, in the YAML tree, before
// validation. Only an existing section map is touched: a missing or malformed section is left
// for the checks to report. An existing key keeps its position (line) in the file; a missing one
// is added.
void override_key(const YAML::Node& root, const char* section, const char* key,
                  const std::string& value) {
  if (value.empty() || !root.IsMap()) return;
  // Const lookups: yaml-cpp's non-const operator[] would add the key it looks for.
  YAML::Node sec = root[section];
  if (!sec.IsDefined() || !sec.IsMap()) return;
  sec[key] = value;
}

void apply_overrides(const YAML::Node& root, const ScenarioOverrides& o) {
  override_key(root, "robot", "preset", o.preset);
  override_key(root, "mission", "strategy", o.strategy);
  if (!o.camera_noise.empty() && root.IsMap()) {
    // robot.camera is an optional partial override: add it when the file has none.
    YAML::Node robot = root["robot"];
    if (robot.IsDefined() && robot.IsMap()) {
      YAML::Node camera = robot["camera"];
      if (!camera.IsDefined()) {
        robot["camera"] = YAML::Node(YAML::NodeType::Map);
        camera = robot["camera"];
      }
      // Parsed as YAML so that it is a plain scalar, checked like the same text in the file.
      if (camera.IsMap()) camera["noise_std"] = YAML::Load(o.camera_noise);
    }
  }
}

std::string describe_overrides(const ScenarioOverrides& o) {
  std::string s;
  if (!o.preset.empty()) s = "robot.preset = " + o.preset;
  if (!o.strategy.empty()) {
    if (!s.empty()) s += ", ";
    s += "mission.strategy = " + o.strategy;
  }
  if (!o.camera_noise.empty()) {
    if (!s.empty()) s += ", ";
    s += "robot.camera.noise_std = " + o.camera_noise;
  }
  return s;
}

// Host code may throw anything (yaml-cpp, bad_alloc); callers only ever see ok/error.
template <typename F>
bool guarded(const std::string& path, std::string& error, F&& body) {
  try {
    body();
    return true;
  } catch (const LoadError& e) {
    error = e.what();
  } catch (const YAML::Exception& e) {
    error = path + ": " + e.what();
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
  } catch (...) {
    error = path + ": unknown error";
  }
  return false;
}

}  // namespace

LoadResult load_scenario(const std::string& path, const std::string& robots_dir,
                         const ScenarioOverrides& overrides) {
  LoadResult r;
  std::string text;
  if (!guarded(path, r.error, [&] { text = strict::read_file(path); })) return r;
  return load_scenario_text(text, path, robots_dir, overrides);
}

LoadResult load_scenario_text(const std::string& text, const std::string& path,
                              const std::string& robots_dir, const ScenarioOverrides& overrides) {
  LoadResult r;
  r.ok = guarded(path, r.error, [&] {
    const Node root = strict::parse_document(text, &path);
    // YAML::Node is a handle: the copy inside shares the tree that root wraps.
    apply_overrides(root.yaml(), overrides);
    r.scenario = parse_scenario(root, path, robots_dir);
  });
  if (!r.ok) {
    r.scenario = Scenario{};
    if (!overrides.empty()) r.error += " (overridden: " + describe_overrides(overrides) + ")";
  }
  return r;
}

bool load_robot_preset(const std::string& path, RobotSpec& out, std::string& error) {
  RobotSpec spec;
  if (!guarded(path, error, [&] { spec = read_preset_file(path); })) return false;
  out = spec;
  return true;
}

std::string default_robots_dir() {
  const char* env = std::getenv("CARRIL_ROBOTS_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  return CARRIL_SOURCE_DIR "/config/robots";
}

bool color_from_name(const std::string& name, Rgb& out) {
  struct Named {
    const char* name;
    Rgb rgb;
  };
  static constexpr Named kColors[] = {
      {"white", {255, 255, 255}}, {"black", {0, 0, 0}},  {"red", {255, 0, 0}},
      {"green", {0, 255, 0}},     {"blue", {0, 0, 255}}, {"yellow", {255, 255, 0}},
  };
  for (const auto& c : kColors) {
    if (name == c.name) {
      out = c.rgb;
      return true;
    }
  }
  return false;
}

}  // namespace carril::sim
