#include "host_sim/scenario/ScenarioLoader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "host_sim/scenario/ScenarioChecks.hpp"
#include "loader/MissionSections.hpp"
#include "loader/OccupancyMapFile.hpp"
#include "loader/RobotSections.hpp"
#include "loader/StrictYaml.hpp"

#ifndef CARRIL_SOURCE_DIR
#define CARRIL_SOURCE_DIR "."
#endif

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

namespace {

using loader::parse_color;
using strict::LoadError;
using strict::Node;
using strict::Range;

// Physical bounds: every accepted value gives a finite, non-degenerate simulation (no inf/NaN in
// geometry, rendering or physics, no Box2D assertion). docs/scenario-format.md lists them all.
const Range kCoord = Range::closed(-1.0e4, 1.0e4);  // world coordinates [m]
const Range kYawDeg = Range::closed(-360.0, 360.0);
const Range kSize = Range::closed(0.01, 100.0);           // obstacle and terrain sizes [m]
const Range kObstacleHeight = Range::closed(0.01, 10.0);  // [m]
const Range kRampAngleDeg = Range::closed(0.5, 30.0);
const Range kRampTop = Range::closed(0.0, 100.0);      // [m]
const Range kStepHeight = Range::closed(-0.5, 0.5);    // [m], |h| >= kMinStepM
const Range kTrenchDepth = Range::closed(0.005, 1.0);  // [m]
constexpr double kMinStepM = 0.005;                    // a smaller step is no step [m]

constexpr double kArcStepM = 0.02;  // max spacing of discretised arc points [m]
constexpr double kMaxArcSweepDeg = 3600.0;

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
constexpr std::size_t kMaxCellExpects = 256;

double deg2rad(double deg) {
  return deg * fw::kPi / 180.0;
}

// ---- Shared value types ----

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

// ---- Scenario sections ----

void parse_robot(const Node& m, const std::string& robots_dir, RobotSpec& robot) {
  m.expect_map({"preset", "start", "camera", "lidar", "limits", "terrain_limits"});
  const Node preset = m.at("preset");
  const std::string name = preset.one_of({"campero", "create3", "pioneer3at"});
  const std::string file = robots_dir + "/" + name + ".yaml";
  try {
    robot = loader::read_robot_file(file);
  } catch (const LoadError& e) {
    preset.fail(std::string("cannot load robot preset: ") + e.what());
  }
  if (robot.preset != name) {
    preset.expected(file + " to declare name: " + name, "name: " + robot.preset);
  }
  // The simulator always simulates the lidar's scans: a robot without one would be given scans
  // its firmware was told it cannot have.
  if (!robot.lidar.present) {
    preset.expected("a robot with a lidar (the simulator always simulates one; " + file +
                    " says lidar.present: false)");
  }
  if (auto s = m.get("start")) {
    s->expect_map({"x", "y", "yaw_deg"});
    robot.start = {s->at("x").number(kCoord), s->at("y").number(kCoord),
                   deg2rad(s->at("yaw_deg").number(kYawDeg))};
  }
  // Overrides: same schema and checks as the preset, every key optional.
  if (auto n = m.get("camera")) {
    loader::parse_camera(*n, robot.camera, false);
    loader::check_camera_view(*n, robot.camera);
  }
  if (auto n = m.get("lidar")) loader::parse_lidar(*n, robot.lidar, false);
  if (auto n = m.get("limits")) loader::parse_limits(*n, robot.limits, false);
  if (auto n = m.get("terrain_limits"))
    loader::parse_terrain_limits(*n, robot.terrain_limits, false);
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
    m.expect_map({"shape", "x", "y", "yaw_deg", "size_m", "height_m"});
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
    m.expect_map({"shape", "x", "y", "radius_m", "height_m"});
    o.shape = ObstacleShape::Cylinder;
    o.radius_m = m.at("radius_m").number(Range::closed(0.01, 50.0));
  }
  o.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  if (auto n = m.get("height_m")) o.height_m = n->number(kObstacleHeight);
  return o;
}

MoverSpec parse_mover(const Node& m) {
  MoverSpec o;
  const std::string shape = m.at("shape").one_of({"box", "cylinder"});
  if (shape == "box") {
    m.expect_map({"shape", "size_m", "path", "speed_mps", "start_s"});
    o.shape = ObstacleShape::Box;
    const Node size = m.at("size_m");
    const auto sz = size.items();
    if (sz.size() != 2) {
      size.expected("[size_x, size_y] (2 numbers)", "a list of " + std::to_string(sz.size()));
    }
    o.size_x_m = sz[0].number(Range::closed(0.05, 20.0));
    o.size_y_m = sz[1].number(Range::closed(0.05, 20.0));
  } else {
    m.expect_map({"shape", "radius_m", "path", "speed_mps", "start_s"});
    o.shape = ObstacleShape::Cylinder;
    o.radius_m = m.at("radius_m").number(Range::closed(0.05, 5.0));
  }
  std::size_t budget = 64;
  o.path = parse_points(m.at("path"), budget, "at most 64 points in a mover's path");
  if (o.path.size() < 2) m.at("path").expected("a path of at least 2 points [x, y]", "1 point");
  // A person walks at up to about 2 m/s, a forklift drives at up to about 5.
  o.speed_mps = m.at("speed_mps").number(Range::closed(0.05, 5.0));
  if (auto n = m.get("start_s")) o.start_s = n->number(Range::closed(0.0, 86400.0));
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
  const std::string type = m.at("type").one_of({"ramp", "step", "trench"});
  if (type == "ramp") {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "angle_deg", "angle2_deg",
                  "length2_m", "top_m", "descend"});
    t.type = TerrainType::Ramp;
    t.angle_deg = m.at("angle_deg").number(kRampAngleDeg);
    // The second section comes whole: an angle without a length (or the reverse) is a mistake.
    const auto a2 = m.get("angle2_deg");
    const auto l2 = m.get("length2_m");
    if (a2 && !l2) m.child_path("length2_m").fail("missing required key (angle2_deg is given)");
    if (l2 && !a2) m.child_path("angle2_deg").fail("missing required key (length2_m is given)");
    if (a2) {
      t.angle2_deg = a2->number(kRampAngleDeg);
      t.length2_m = l2->number(kSize);
    }
    if (auto n = m.get("top_m")) t.top_m = n->number(kRampTop);
    if (auto n = m.get("descend")) t.descend = n->boolean();
  } else if (type == "step") {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "height_m"});
    t.type = TerrainType::Step;
    const Node h = m.at("height_m");
    t.height_m = h.number(kStepHeight);
    if (std::abs(t.height_m) < kMinStepM) {
      h.expected("a number in [-0.5, -0.005] or [0.005, 0.5] (a raised platform or a pit)",
                 h.raw());
    }
  } else {
    m.expect_map({"type", "x", "y", "yaw_deg", "length_m", "width_m", "depth_m"});
    t.type = TerrainType::Trench;
    t.depth_m = m.at("depth_m").number(kTrenchDepth);
  }
  t.center = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  if (auto n = m.get("yaw_deg")) t.yaw_rad = deg2rad(n->number(kYawDeg));
  t.length_m = m.at("length_m").number(kSize);
  t.width_m = m.at("width_m").number(kSize);
  return t;
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

CellExpect parse_cell_expect(const Node& m) {
  m.expect_map({"x", "y", "label", "layer", "what"});
  CellExpect c;
  c.at = {m.at("x").number(kCoord), m.at("y").number(kCoord)};
  const std::string label = m.at("label").one_of({"free", "passable", "lethal", "unknown"});
  c.label = label == "free"       ? CellLabel::Free
            : label == "passable" ? CellLabel::Passable
            : label == "lethal"   ? CellLabel::Lethal
                                  : CellLabel::Unknown;
  if (auto n = m.get("layer")) {
    const std::string layer = n->one_of({"master", "traversability", "obstacle"});
    c.layer = layer == "master"           ? CellLayer::Master
              : layer == "traversability" ? CellLayer::Traversability
                                          : CellLayer::Obstacle;
  }
  if (auto n = m.get("what")) c.what = n->string();
  return c;
}

KidnapSpec parse_kidnap(const Node& m) {
  m.expect_map({"t_s", "x", "y", "yaw_deg"});
  KidnapSpec k;
  k.t_s = m.at("t_s").number(Range::closed(0.0, 86400.0));
  k.to = {m.at("x").number(kCoord), m.at("y").number(kCoord),
          deg2rad(m.at("yaw_deg").number(kYawDeg))};
  return k;
}

LocalisationSpec parse_localisation(const Node& m) {
  // The keys a robot's mission file has too (loader/MissionSections.hpp), and the kidnaps.
  loader::LocalisationStartSpec start;
  loader::parse_localisation_start(m, {"kidnap"}, start);
  LocalisationSpec l;
  l.initial_sigma_xy_m = start.initial_sigma_xy_m;
  l.initial_sigma_yaw_rad = start.initial_sigma_yaw_rad;
  l.recovery = start.recovery;
  l.max_unlocalised_s = start.max_unlocalised_s;
  l.global = start.global;
  if (start.has_initial_pose) {
    l.initial_pose =
        Pose2{start.initial_pose.x_m, start.initial_pose.y_m, deg2rad(start.initial_pose.yaw_deg)};
  }
  l.kidnaps = parse_list<KidnapSpec>(m.get("kidnap"), 16, "kidnap", parse_kidnap);
  for (std::size_t i = 1; i < l.kidnaps.size(); ++i) {
    if (l.kidnaps[i].t_s <= l.kidnaps[i - 1].t_s) {
      m.at("kidnap").expected("kidnaps in increasing t_s", "t_s not increasing");
    }
  }
  return l;
}

OdometryErrorSpec parse_odometry(const Node& m) {
  m.expect_map({"wheel_radius_error", "slip"});
  OdometryErrorSpec o;
  if (auto n = m.get("wheel_radius_error")) {
    o.wheel_radius_error = n->number(Range::closed(-0.2, 0.2));
  }
  if (auto n = m.get("slip")) o.slip = n->number(Range::closed(0.0, 0.5));
  return o;
}

TapeWearSpec parse_tape_wear(const Node& m) {
  m.expect_map({"gaps_per_m", "gap_length_m", "fade"});
  TapeWearSpec w;
  if (auto n = m.get("gaps_per_m")) w.gaps_per_m = n->number(Range::closed(0.0, 5.0));
  if (auto n = m.get("gap_length_m")) w.gap_length_m = n->number(Range::closed(0.005, 2.0));
  if (auto n = m.get("fade")) w.fade = n->number(Range::closed(0.0, 1.0));
  return w;
}

GlareSpec parse_glare(const Node& m) {
  m.expect_map({"intensity", "radius_px", "period_s"});
  GlareSpec g;
  g.intensity = m.at("intensity").number(Range::closed(0.0, 255.0));
  if (auto n = m.get("radius_px")) g.radius_px = n->number(Range::closed(1.0, 2000.0));
  if (auto n = m.get("period_s")) g.period_s = n->number(Range::closed(0.1, 3600.0));
  return g;
}

ExpectSpec parse_expect(const Node& m) {
  m.expect_map({"end_reached", "max_collisions", "max_cross_track_rms_m", "min_progress",
                "min_laps", "max_end_stop_error_m", "goal_reached", "max_goal_error_m",
                "max_goal_yaw_error_deg", "fault", "min_replans", "cells", "min_coverage",
                "max_coverage_time_ratio", "max_time_to_converge_s", "max_relocalise_s",
                "max_localisation_rmse_m"});
  ExpectSpec e;
  if (auto n = m.get("max_time_to_converge_s")) {
    e.max_time_to_converge_s = n->number(Range::closed(0.0, 86400.0));
  }
  if (auto n = m.get("max_relocalise_s")) {
    e.max_relocalise_s = n->number(Range::closed(0.0, 86400.0));
  }
  if (auto n = m.get("max_localisation_rmse_m")) {
    e.max_localisation_rmse_m = n->number(Range::open_closed(0.0, 10.0));
  }
  if (auto n = m.get("goal_reached")) e.goal_reached = n->boolean();
  if (auto n = m.get("max_goal_error_m")) {
    e.max_goal_error_m = n->number(Range::open_closed(0.0, 10.0));
  }
  if (auto n = m.get("max_goal_yaw_error_deg")) {
    e.max_goal_yaw_error_deg = n->number(Range::open_closed(0.0, 180.0));
  }
  if (auto n = m.get("fault")) {
    e.fault = n->one_of({"no_path", "goal_invalid", "path_blocked", "line_not_found",
                         "no_coverage_area", "not_localised", "stalled", "motion_blocked"});
  }
  if (auto n = m.get("min_coverage")) e.min_coverage = n->number(Range::closed(0.0, 1.0));
  if (auto n = m.get("max_coverage_time_ratio")) {
    e.max_coverage_time_ratio = n->number(Range::open_closed(0.0, 100.0));
  }
  if (auto n = m.get("min_replans")) e.min_replans = static_cast<int>(n->integer(0, 1000000));
  e.cells = parse_list<CellExpect>(m.get("cells"), kMaxCellExpects, "cells", parse_cell_expect);
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

// `map: FILE.yaml`, relative to the scenario file: the map loader's message on `map` when it
// cannot be loaded.
void parse_map(const Node& n, const std::string& scenario_path, Scenario& s) {
  const std::string file = n.string();
  if (file.empty()) n.expected("a map file (ROS map_server YAML)", "an empty string");
  s.map_path = (std::filesystem::path(scenario_path).parent_path() / file).string();
  loader::OccupancyMapLoad m = loader::load_occupancy_map(s.map_path, loader::kMaxMapCells);
  if (!m.ok()) n.fail("cannot load the map: " + m.error);
  s.map = std::make_shared<const loader::OccupancyMapData>(std::move(m.map));
}

Scenario parse_scenario(const Node& root, const std::string& path, const std::string& robots_dir) {
  root.expect_map({"name", "description", "duration_s", "seed", "floor", "robot", "mission",
                   "lines", "marks", "obstacles", "movers", "walls", "terrain", "map",
                   "localisation", "odometry", "tape_wear", "glare", "expect"});
  Scenario s;
  s.source_path = path;
  s.name = strict::parse_name(root.at("name"));
  if (auto n = root.get("description")) s.description = n->string();
  s.duration_s = root.at("duration_s").number(Range::closed(0.1, 86400.0));
  if (auto n = root.get("seed")) s.seed = n->unsigned_integer();
  if (auto n = root.get("floor")) {
    n->expect_map({"color", "speckle"});
    s.floor = parse_color(n->at("color"));
    if (auto k = n->get("speckle")) s.floor_speckle = k->number(Range::closed(0.0, 0.3));
  }
  parse_robot(root.at("robot"), robots_dir, s.robot);
  loader::parse_mission(root.at("mission"), s.robot, loader::MissionSchema{}, s.mission);
  const auto lines = root.get("lines");
  std::size_t tape_budget = kMaxTapePoints;
  s.lines = parse_list<LineSpec>(lines, kMaxLines, "lines",
                                 [&](const Node& n) { return parse_line(n, tape_budget); });
  s.marks = parse_list<MarkSpec>(root.get("marks"), kMaxMarks, "marks", parse_mark);
  s.obstacles =
      parse_list<ObstacleSpec>(root.get("obstacles"), kMaxObstacles, "obstacles", parse_obstacle);
  s.movers = parse_list<MoverSpec>(root.get("movers"), 32, "movers", parse_mover);
  std::size_t wall_budget = kMaxWallPoints;
  s.walls = parse_list<WallSpec>(root.get("walls"), kMaxWalls, "walls",
                                 [&](const Node& n) { return parse_wall(n, wall_budget); });
  s.terrain =
      parse_list<TerrainSpec>(root.get("terrain"), kMaxTerrain, "terrain items", parse_terrain);
  if (auto n = root.get("map")) parse_map(*n, path, s);
  if (auto n = root.get("localisation")) {
    s.localisation = parse_localisation(*n);
    if (!s.map) n->expected("a map: (localisation runs on a known map)", "no map");
  }
  if (auto n = root.get("odometry")) s.odometry = parse_odometry(*n);
  if (auto n = root.get("tape_wear")) s.tape_wear = parse_tape_wear(*n);
  if (auto n = root.get("glare")) s.glare = parse_glare(*n);
  if (auto n = root.get("expect")) {
    s.expect = parse_expect(*n);
    // Localisation is scored only on a map, and a relocalisation only after a kidnap.
    for (const char* k :
         {"max_time_to_converge_s", "max_relocalise_s", "max_localisation_rmse_m"}) {
      if (auto e = n->get(k); e && !s.map) {
        e->expected("a map: (localisation is scored on a known map)", "no map");
      }
    }
    if (auto e = n->get("max_relocalise_s"); e && s.localisation.kidnaps.empty()) {
      e->expected("a kidnap in localisation.kidnap", "none");
    }
  }

  // follow_line needs tape of the mission's colour to follow.
  const bool has_line = std::any_of(s.lines.begin(), s.lines.end(), [&](const LineSpec& l) {
    return l.color == s.mission.line_color;
  });
  if (s.mission.type == "follow_line" && !has_line) {
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

}  // namespace

LoadResult load_scenario(const std::string& path, const std::string& robots_dir,
                         const ScenarioOverrides& overrides) {
  LoadResult r;
  std::string text;
  if (!strict::guarded(path, r.error, [&] { text = strict::read_file(path); })) return r;
  return load_scenario_text(text, path, robots_dir, overrides);
}

LoadResult load_scenario_text(const std::string& text, const std::string& path,
                              const std::string& robots_dir, const ScenarioOverrides& overrides) {
  LoadResult r;
  r.ok = strict::guarded(path, r.error, [&] {
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

std::string default_robots_dir() {
  const char* env = std::getenv("CARRIL_ROBOTS_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  return CARRIL_SOURCE_DIR "/config/robots";
}

}  // namespace carril::sim
