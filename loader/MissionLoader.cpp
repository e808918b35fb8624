#include "loader/MissionLoader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <vector>

#include "loader/ColorThreshold.hpp"
#include "loader/MissionSections.hpp"
#include "loader/SettingsYaml.hpp"

namespace carril::loader {

using strict::Node;
using strict::Range;

namespace {

// The fastest the wheels can carry the body: wheel radius x wheel speed limit.
double wheel_speed_limit_mps(const RobotSpec& r) {
  return r.wheel_radius_m * r.limits.max_wheel_speed_radps;
}

// The detector must tell the tape from the end mark (a scenario checks this with its floor, in
// ScenarioChecks; a mission file has no floor).
void check_end_color(const Node& root, const MissionSpec& m) {
  const bool line_as_end =
      detector_sees(detector_threshold(m.end_color_name, m.end_color), m.line_color);
  const bool end_as_line =
      detector_sees(detector_threshold(m.line_color_name, m.line_color), m.end_color);
  if (!line_as_end && !end_as_line) return;
  const auto n = root.get("end_color");
  const Node where = n ? *n : root.child_path("end_color");
  where.expected("an end colour the detector tells from line_color " + m.line_color_name + " (" +
                     (line_as_end ? "the tape falls in the end window"
                                  : "the end colour falls in the tape window") +
                     ")",
                 m.end_color_name);
}

GoalSpec parse_goal(const Node& goal);

// A mission file's keys for a mission on a known map (map:, localisation:) besides `keys`; a
// scenario writes those at its top level.
std::vector<std::string> with_map_keys(const MissionSchema& schema,
                                       std::initializer_list<const char*> keys) {
  std::vector<std::string> out(keys.begin(), keys.end());
  if (schema.file) {
    out.emplace_back("map");
    out.emplace_back("localisation");
  }
  return out;
}

// A mission file's map: and localisation: (goto, waypoints, coverage). The map's path is
// resolved against the file's folder by load_mission.
void parse_map_keys(const Node& m, const MissionSchema& schema, MissionSpec& mission) {
  if (!schema.file) return;
  if (auto n = m.get("map")) {
    mission.map_path = n->string();
    if (mission.map_path.empty())
      n->expected("a map file (ROS map_server YAML)", "an empty string");
  }
  if (auto n = m.get("localisation")) {
    if (mission.map_path.empty()) n->expected("localisation only with a map:", "no map");
    parse_localisation_start(*n, {}, mission.localisation);
  }
}

// A list of min_n to max_n points [x, y] (yaw 0), as waypoint targets and area corners are written;
// `what` names the items in the message ("targets").
std::vector<GoalSpec> parse_points(const Node& list, std::size_t min_n, std::size_t max_n,
                                   const char* what) {
  const auto items = list.items();
  if (items.size() < min_n || items.size() > max_n) {
    list.expected("a list of " + std::to_string(min_n) + " to " + std::to_string(max_n) + " " +
                      what + " [x, y]",
                  std::to_string(items.size()) + " " + what);
  }
  std::vector<GoalSpec> out;
  for (const Node& t : items) {
    const auto xy = t.items();
    if (xy.size() != 2) t.expected("a point [x, y]", "a list of " + std::to_string(xy.size()));
    out.push_back(GoalSpec{xy[0].number(Range::closed(-1000.0, 1000.0)),
                           xy[1].number(Range::closed(-1000.0, 1000.0)), 0.0});
  }
  return out;
}
void parse_coverage(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                    MissionSpec& mission);
void parse_speed(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                 MissionSpec& mission);

// goto: the goal pose, the speed (as follow_line's), the local follower and unknown cells.
void parse_goto(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                MissionSpec& mission) {
  m.expect_map(
      with_map_keys(schema, {"type", "goal", "goals", "speed_mps", "follower", "allow_unknown"}));
  const auto one = m.get("goal");
  const auto many = m.get("goals");
  if (one && many) m.expected("exactly one of goal or goals", "both");
  if (!one && !many) m.expected("exactly one of goal or goals", "neither");
  if (one) {
    const GoalSpec g = parse_goal(*one);
    mission.goal_x_m = g.x_m;
    mission.goal_y_m = g.y_m;
    mission.goal_yaw_deg = g.yaw_deg;
  } else {
    const auto items = many->items();
    if (items.empty() || items.size() > 16) {
      many->expected("a list of 1 to 16 goals", std::to_string(items.size()) + " goals");
    }
    for (const Node& g : items) mission.goals.push_back(parse_goal(g));
    mission.goal_x_m = mission.goals.back().x_m;
    mission.goal_y_m = mission.goals.back().y_m;
    mission.goal_yaw_deg = mission.goals.back().yaw_deg;
  }
  if (auto f = m.get("follower")) mission.follower = f->one_of({"pure_pursuit", "vff"});
  if (auto u = m.get("allow_unknown")) mission.allow_unknown = u->boolean();
  parse_speed(m, robot, schema, mission);
  parse_map_keys(m, schema, mission);
}

// waypoints: targets driven to in turn with VFF, no planner (the course's avoidance practice).
void parse_waypoints(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                     MissionSpec& mission) {
  m.expect_map(with_map_keys(schema, {"type", "targets", "laps", "reach_radius_m", "speed_mps"}));
  mission.targets = parse_points(m.at("targets"), 1, 32, "targets");
  if (auto n = m.get("laps")) mission.laps = static_cast<int>(n->integer(1, 100));
  if (auto n = m.get("reach_radius_m"))
    mission.reach_radius_m = n->number(Range::closed(0.05, 2.0));
  parse_speed(m, robot, schema, mission);
  parse_map_keys(m, schema, mission);
}

// A coverage area must be a simple polygon with an area: crossing edges leave its inside
// undefined (the lanes would be cut by whichever rule the planner happens to use).
void check_simple_polygon(const Node& n, const std::vector<GoalSpec>& p) {
  const std::size_t k = p.size();
  auto cross = [](const GoalSpec& o, const GoalSpec& a, const GoalSpec& b) {
    return (a.x_m - o.x_m) * (b.y_m - o.y_m) - (a.y_m - o.y_m) * (b.x_m - o.x_m);
  };
  double twice_area = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    const GoalSpec &a = p[i], &b = p[(i + 1) % k];
    twice_area += a.x_m * b.y_m - b.x_m * a.y_m;
    for (std::size_t j = i + 1; j < k; ++j) {
      if (j == i || (j + 1) % k == i || (i + 1) % k == j)
        continue;  // adjacent edges share a corner
      const GoalSpec &c = p[j], &d = p[(j + 1) % k];
      const double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c),
                   d4 = cross(a, b, d);
      const bool proper = ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 &&
                          d3 != 0 && d4 != 0;
      const auto on = [](const GoalSpec& s0, const GoalSpec& s1, const GoalSpec& q, double side) {
        return side == 0 && std::min(s0.x_m, s1.x_m) <= q.x_m && q.x_m <= std::max(s0.x_m, s1.x_m) &&
               std::min(s0.y_m, s1.y_m) <= q.y_m && q.y_m <= std::max(s0.y_m, s1.y_m);
      };
      if (proper || on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4)) {
        n.expected("the corners of a simple polygon (edges that do not cross or touch)",
                   "edge " + std::to_string(i + 1) + "-" + std::to_string((i + 1) % k + 1) +
                       " meeting edge " + std::to_string(j + 1) + "-" +
                       std::to_string((j + 1) % k + 1));
      }
    }
  }
  if (std::fabs(twice_area) < 1e-6) {
    n.expected("the corners of a polygon with an area", "corners on one line");
  }
}

// coverage: the mode, the tool, the area and a time limit.
void parse_coverage(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                    MissionSpec& mission) {
  m.expect_map(
      with_map_keys(schema, {"type", "mode", "tool_width_m", "wall_clearance_m", "area",
                             "max_time_s", "speed_mps", "transit_speed_mps", "lane_overlap"}));
  if (auto n = m.get("mode")) mission.coverage_mode = n->one_of({"systematic", "vacuum"});
  if (auto n = m.get("tool_width_m")) mission.tool_width_m = n->number(Range::closed(0.05, 3.0));
  if (auto n = m.get("wall_clearance_m")) {
    mission.wall_clearance_m = n->number(Range::closed(0.0, 1.0));
  }
  if (auto n = m.get("max_time_s")) mission.max_time_s = n->number(Range::closed(1.0, 86400.0));
  if (auto a = m.get("area")) {
    mission.area = parse_points(*a, 3, 16, "corners");
    check_simple_polygon(*a, mission.area);
  }
  if (auto n = m.get("lane_overlap")) mission.lane_overlap = n->number(Range::closed(0.0, 0.5));
  parse_speed(m, robot, schema, mission);
  // Transits cross floor already swept (or to be swept): up to the robot's top speed.
  if (auto n = m.get("transit_speed_mps")) {
    const double max_speed = robot.limits.max_speed_mps;
    mission.transit_speed_mps = n->number(Range::closed(0.01, 5.0));
    if (mission.transit_speed_mps > max_speed) {
      n->expected(
          "a number in (0, " + schema.speed_limit + " = " + strict::format_number(max_speed) + "]",
          n->raw());
    }
  }
  parse_map_keys(m, schema, mission);
  if (schema.file && mission.coverage_mode == "systematic" && mission.map_path.empty()) {
    m.child_path("map").expected("a map file: a systematic coverage mission plans on a map",
                                 "nothing");
  }
}

GoalSpec parse_goal(const Node& goal) {
  goal.expect_map({"x", "y", "yaw_deg"});
  return {goal.at("x").number(Range::closed(-1000.0, 1000.0)),
          goal.at("y").number(Range::closed(-1000.0, 1000.0)),
          goal.at("yaw_deg").number(Range::closed(-360.0, 360.0))};
}

void parse_speed(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                 MissionSpec& mission) {
  const double max_speed = robot.limits.max_speed_mps;
  if (auto n = m.get("speed_mps")) {
    mission.speed_mps = n->number(Range::closed(0.01, 5.0));
    if (mission.speed_mps > max_speed) {
      n->expected(
          "a number in (0, " + schema.speed_limit + " = " + strict::format_number(max_speed) + "]",
          n->raw());
    }
  } else {
    mission.speed_mps = std::min(robot.cruise_speed_mps, max_speed);
  }
}

}  // namespace

Rgb parse_color(const Node& n, std::string* name_out) {
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

void parse_localisation_start(const Node& m, std::initializer_list<const char*> extra_keys,
                              LocalisationStartSpec& out) {
  std::vector<std::string> keys{"initial_pose",          "global",   "initial_sigma_xy_m",
                                "initial_sigma_yaw_deg", "recovery", "max_unlocalised_s"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  m.expect_map(keys);
  if (auto n = m.get("initial_sigma_xy_m")) {
    out.initial_sigma_xy_m = n->number(Range::closed(0.01, 10.0));
  }
  if (auto n = m.get("initial_sigma_yaw_deg")) {
    out.initial_sigma_yaw_rad = n->number(Range::closed(0.5, 180.0)) * std::numbers::pi / 180.0;
  }
  if (auto n = m.get("recovery")) out.recovery = n->boolean();
  if (auto n = m.get("max_unlocalised_s")) {
    out.max_unlocalised_s = n->number(Range::closed(0.0, 86400.0));
  }
  if (auto n = m.get("initial_pose")) {
    out.initial_pose = parse_goal(*n);
    out.has_initial_pose = true;
  }
  if (auto n = m.get("global")) out.global = n->boolean();
  if (out.global && out.has_initial_pose) {
    m.at("global").expected("no initial_pose with global: true", "both");
  }
}

void parse_mission(const Node& m, const RobotSpec& robot, const MissionSchema& schema,
                   MissionSpec& mission) {
  if (auto t = m.get("type"); t && t->yaml().IsScalar() && t->string() == "goto") {
    mission.type = "goto";
    parse_goto(m, robot, schema, mission);
    return;
  }
  if (auto t = m.get("type"); t && t->yaml().IsScalar() && t->string() == "coverage") {
    mission.type = "coverage";
    parse_coverage(m, robot, schema, mission);
    return;
  }
  if (auto t = m.get("type"); t && t->yaml().IsScalar() && t->string() == "waypoints") {
    mission.type = "waypoints";
    parse_waypoints(m, robot, schema, mission);
    return;
  }
  if (schema.file) {
    m.expect_map({"type", "strategy", "line_color", "end_color", "speed_mps", "tape_preview_m",
                  "behavior", "strategy_gains"});
  } else {
    m.expect_map({"type", "strategy", "line_color", "end_color", "speed_mps"});
  }
  const Node type = m.at("type");
  mission.type = type.one_of({"follow_line", "goto", "waypoints", "coverage"});
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
      "a number in (0, " + schema.speed_limit + " = " + strict::format_number(max_speed) + "]";
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
  if (schema.file) {
    for (const char* key : {"tape_preview_m", "behavior", "strategy_gains"}) {
      if (auto n = m.get(key)) parse_settings(*n, SettingFile::Mission, mission.settings);
    }
  }
}

bool load_mission(const std::string& path, const RobotSpec& robot, MissionSpec& out,
                  std::string& error) {
  MissionSpec mission;
  const bool ok = strict::guarded(path, error, [&] {
    const Node root = strict::parse_document(strict::read_file(path), &path);
    MissionSchema schema;
    schema.file = true;
    schema.speed_limit = "the robot's limits.max_speed_mps";
    parse_mission(root, robot, schema, mission);
    check_end_color(root, mission);
    mission.source_path = path;
    if (!mission.map_path.empty()) {
      mission.map_path = (std::filesystem::path(path).parent_path() / mission.map_path)
                             .lexically_normal()
                             .string();
    }
  });
  if (ok) out = mission;
  return ok;
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

}  // namespace carril::loader
