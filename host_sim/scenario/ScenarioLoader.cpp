#include "host_sim/scenario/ScenarioLoader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "host_sim/scenario/StrictYaml.hpp"

#ifndef CARRIL_SOURCE_DIR
#define CARRIL_SOURCE_DIR "."
#endif

namespace carril::sim {

namespace {

using strict::LoadError;
using strict::Node;
using strict::Range;

// Bounds that keep every later computation (geometry, physics, rendering) far from overflow.
const Range kCoord = Range::closed(-1.0e4, 1.0e4);  // world coordinates [m]
const Range kYawDeg = Range::closed(-360.0, 360.0);
const Range kMount = Range::closed(-10.0, 10.0);  // sensor mount offsets [m]
const Range kSize = Range::open_closed(0.0, 100.0);

constexpr double kArcStepM = 0.02;  // max spacing of discretised arc points [m]
constexpr double kMaxArcSweepDeg = 3600.0;
constexpr std::size_t kMaxNameLength = 64;

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

std::vector<Vec2> parse_points(const Node& n) {
  std::vector<Vec2> out;
  for (const Node& p : n.items(2)) out.push_back(parse_point(p));
  return out;
}

// ---- Robot preset blocks; `all` = every key required (preset file) or optional (override) ----

void parse_camera(const Node& m, CameraSpec& c, bool all) {
  m.expect_map(
      {"x_m", "y_m", "z_m", "tilt_deg", "hfov_deg", "width", "height", "rate_hz", "noise_std"});
  if (auto n = m.get("x_m", all)) c.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) c.y_m = n->number(kMount);
  if (auto n = m.get("z_m", all)) c.z_m = n->number(Range::open_closed(0.0, 10.0));
  if (auto n = m.get("tilt_deg", all)) c.tilt_deg = n->number(Range::open_closed(0.0, 90.0));
  if (auto n = m.get("hfov_deg", all)) c.hfov_deg = n->number(Range::open(10.0, 170.0));
  // The firmware's image buffer is fixed at hal::kMaxImageWidth x kMaxImageHeight.
  if (auto n = m.get("width", all)) c.width = static_cast<int>(n->integer(32, 1280));
  if (auto n = m.get("height", all)) c.height = static_cast<int>(n->integer(32, 960));
  if (auto n = m.get("rate_hz", all)) c.rate_hz = n->number(Range::open_closed(0.0, 1000.0));
  if (auto n = m.get("noise_std", all)) c.noise_std = n->number(Range::closed(0.0, 255.0));
}

void parse_lidar(const Node& m, LidarSpec& l, bool all) {
  m.expect_map({"x_m", "y_m", "yaw_deg", "fov_deg", "beams", "range_min_m", "range_max_m",
                "rate_hz", "noise_std_m"});
  if (auto n = m.get("x_m", all)) l.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) l.y_m = n->number(kMount);
  if (auto n = m.get("yaw_deg", all)) l.yaw_deg = n->number(kYawDeg);
  if (auto n = m.get("fov_deg", all)) l.fov_deg = n->number(Range::open_closed(0.0, 360.0));
  // hal::kMaxScanBeams.
  if (auto n = m.get("beams", all)) l.beams = static_cast<int>(n->integer(2, 2048));
  const auto max_n = m.get("range_max_m", all);
  const auto min_n = m.get("range_min_m", all);
  if (max_n) l.range_max_m = max_n->number(Range::open_closed(0.0, 1000.0));
  if (min_n) {
    l.range_min_m = min_n->number(Range::non_negative());
    if (l.range_min_m >= l.range_max_m) {
      min_n->expected("a number in [0, range_max_m = " + strict::format_number(l.range_max_m) + ")",
                      min_n->raw());
    }
  } else if (max_n && l.range_max_m <= l.range_min_m) {
    max_n->expected(
        "a number in (range_min_m = " + strict::format_number(l.range_min_m) + ", 1000]",
        max_n->raw());
  }
  if (auto n = m.get("rate_hz", all)) l.rate_hz = n->number(Range::open_closed(0.0, 1000.0));
  if (auto n = m.get("noise_std_m", all)) l.noise_std_m = n->number(Range::closed(0.0, 10.0));
}

void parse_limits(const Node& m, LimitsSpec& l, bool all) {
  m.expect_map({"max_speed_mps", "max_yaw_rate_radps", "max_accel_mps2", "max_wheel_speed_radps",
                "max_wheel_accel_radps2"});
  auto pos = [&](const char* key, double hi, double& out) {
    if (auto n = m.get(key, all)) out = n->number(Range::open_closed(0.0, hi));
  };
  pos("max_speed_mps", 20.0, l.max_speed_mps);
  pos("max_yaw_rate_radps", 20.0, l.max_yaw_rate_radps);
  pos("max_accel_mps2", 50.0, l.max_accel_mps2);
  pos("max_wheel_speed_radps", 1000.0, l.max_wheel_speed_radps);
  pos("max_wheel_accel_radps2", 10000.0, l.max_wheel_accel_radps2);
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
  r.length_m = body.at("length_m").number(Range::open_closed(0.0, 10.0));
  r.width_m = body.at("width_m").number(Range::open_closed(0.0, 10.0));
  r.mass_kg = body.at("mass_kg").number(Range::open_closed(0.0, 10000.0));
  const Node wheels = root.at("wheels");
  wheels.expect_map({"radius_m", "wheelbase_m", "track_m"});
  r.wheel_radius_m = wheels.at("radius_m").number(Range::open_closed(0.0, 2.0));
  r.wheelbase_m = wheels.at("wheelbase_m").number(Range::open_closed(0.0, 10.0));
  r.track_m = wheels.at("track_m").number(Range::open_closed(0.0, 10.0));
  r.control_rate_hz = root.at("control_rate_hz").number(Range::closed(10.0, 1000.0));
  parse_camera(root.at("camera"), r.camera, true);
  parse_lidar(root.at("lidar"), r.lidar, true);
  parse_limits(root.at("limits"), r.limits, true);
  const Node cruise = root.at("cruise_speed_mps");
  r.cruise_speed_mps = cruise.number(Range::positive());
  if (r.cruise_speed_mps > r.limits.max_speed_mps) {
    cruise.expected("a number in (0, limits.max_speed_mps = " +
                        strict::format_number(r.limits.max_speed_mps) + "]",
                    cruise.raw());
  }
  return r;
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
  if (auto n = m.get("camera")) parse_camera(*n, robot.camera, false);
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
  if (auto n = m.get("speed_mps")) {
    mission.speed_mps = n->number(Range::positive());
    if (mission.speed_mps > max_speed) n->expected(speed_range, n->raw());
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

LineSpec parse_line(const Node& m) {
  m.expect_map({"color", "width_m", "points", "arc"});
  LineSpec line;
  line.color = parse_color(m.at("color"));
  if (auto n = m.get("width_m")) line.width_m = n->number(Range::open_closed(0.0, 0.5));
  const auto points = m.get("points");
  const auto arc = m.get("arc");
  if (points && arc) m.expected("exactly one of points or arc", "both");
  if (!points && !arc) m.expected("exactly one of points or arc", "neither");
  if (points) {
    line.points = parse_points(*points);
    return line;
  }
  arc->expect_map({"center", "radius_m", "start_deg", "end_deg"});
  const Vec2 center = parse_point(arc->at("center"));
  const double radius = arc->at("radius_m").number(Range::open_closed(0.0, 100.0));
  const double start = arc->at("start_deg").number(Range::closed(-3600.0, 3600.0));
  const Node end_n = arc->at("end_deg");
  const double end = end_n.number(Range::closed(-3600.0, 3600.0));
  const double sweep = std::abs(end - start);
  if (sweep == 0.0 || sweep > kMaxArcSweepDeg) {
    end_n.expected("a number != start_deg and within 3600 of it (start_deg = " +
                       strict::format_number(start) + ")",
                   end_n.raw());
  }
  line.points = discretise_arc(center, radius, start, end);
  line.from_arc = true;
  return line;
}

MarkSpec parse_mark(const Node& m) {
  m.expect_map({"color", "x", "y", "radius_m"});
  MarkSpec mark;
  mark.color = parse_color(m.at("color"));
  mark.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  if (auto n = m.get("radius_m")) mark.radius_m = n->number(Range::open_closed(0.0, 2.0));
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
    o.radius_m = m.at("radius_m").number(Range::open_closed(0.0, 50.0));
  }
  o.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  return o;
}

WallSpec parse_wall(const Node& m) {
  m.expect_map({"points", "thickness_m"});
  WallSpec w;
  w.points = parse_points(m.at("points"));
  if (auto n = m.get("thickness_m")) w.thickness_m = n->number(Range::open_closed(0.0, 10.0));
  return w;
}

TerrainSpec parse_terrain(const Node& m) {
  TerrainSpec t;
  const std::string type = m.at("type").one_of({"ramp", "step"});
  if (type == "ramp") {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "angle_deg"});
    t.type = TerrainType::Ramp;
    t.angle_deg = m.at("angle_deg").number(Range::open(0.0, 45.0));
  } else {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "height_m"});
    t.type = TerrainType::Step;
    t.height_m = m.at("height_m").number(Range::open_closed(0.0, 1.0));
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
    e.max_cross_track_rms_m = n->number(Range::positive());
  }
  if (auto n = m.get("min_progress")) e.min_progress = n->number(Range::closed(0.0, 1.0));
  if (auto n = m.get("min_laps")) e.min_laps = static_cast<int>(n->integer(0, 1000000));
  if (auto n = m.get("max_end_stop_error_m")) {
    e.max_end_stop_error_m = n->number(Range::positive());
  }
  return e;
}

template <typename T, typename F>
std::vector<T> parse_list(const std::optional<Node>& n, F parse_item) {
  std::vector<T> out;
  if (!n) return out;
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
  s.duration_s = root.at("duration_s").number(Range::open_closed(0.0, 86400.0));
  if (auto n = root.get("seed")) s.seed = n->unsigned_integer();
  if (auto n = root.get("floor")) {
    n->expect_map({"color"});
    s.floor = parse_color(n->at("color"));
  }
  parse_robot(root.at("robot"), robots_dir, s.robot);
  parse_mission(root.at("mission"), s.robot, s.mission);
  const auto lines = root.get("lines");
  s.lines = parse_list<LineSpec>(lines, parse_line);
  s.marks = parse_list<MarkSpec>(root.get("marks"), parse_mark);
  s.obstacles = parse_list<ObstacleSpec>(root.get("obstacles"), parse_obstacle);
  s.walls = parse_list<WallSpec>(root.get("walls"), parse_wall);
  s.terrain = parse_list<TerrainSpec>(root.get("terrain"), parse_terrain);
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
}

std::string describe_overrides(const ScenarioOverrides& o) {
  std::string s;
  if (!o.preset.empty()) s = "robot.preset = " + o.preset;
  if (!o.strategy.empty()) {
    if (!s.empty()) s += ", ";
    s += "mission.strategy = " + o.strategy;
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
