#include "host_sim/scenario/ScenarioChecks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/scenario/ColorCheck.hpp"
#include "loader/OccupancyMapFile.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

using strict::Node;

namespace {

// An oriented rectangle: centre, heading, half extents.
struct Obb {
  Vec2 c;
  double yaw = 0.0, hx = 0.0, hy = 0.0;
};

// Strict overlap (touching is not overlap), by the separating axis test.
bool overlaps(const Obb& a, const Obb& b) {
  const double dx = b.c.x - a.c.x, dy = b.c.y - a.c.y;
  const Obb* boxes[2] = {&a, &b};
  for (const Obb* axis_box : boxes) {
    for (int k = 0; k < 2; ++k) {
      const double ang = axis_box->yaw + (k == 0 ? 0.0 : fw::kPi / 2);
      const double ax = std::cos(ang), ay = std::sin(ang);
      double reach = 0.0;
      for (const Obb* o : boxes) {
        const double co = std::cos(o->yaw), si = std::sin(o->yaw);
        reach += o->hx * std::abs(co * ax + si * ay) + o->hy * std::abs(-si * ax + co * ay);
      }
      if (std::abs(dx * ax + dy * ay) >= reach) return false;
    }
  }
  return true;
}

bool overlaps(const Obb& a, Vec2 centre, double radius) {
  const double co = std::cos(a.yaw), si = std::sin(a.yaw);
  const double dx = centre.x - a.c.x, dy = centre.y - a.c.y;
  const double lx = co * dx + si * dy, ly = -si * dx + co * dy;
  const double qx = lx - std::clamp(lx, -a.hx, a.hx), qy = ly - std::clamp(ly, -a.hy, a.hy);
  return std::hypot(qx, qy) < radius;
}

// The map's occupied cells are walls (SimWorld builds them exactly): the footprint may touch
// them but not overlap one. Only the cells under the footprint's bounding box are looked at.
void check_start_clear_of_map(const Obb& robot, const loader::OccupancyMapData& map,
                              const Node& where, const std::string& what, const std::string& got) {
  const fw::MapInfo& m = map.info;
  const double co = std::abs(std::cos(robot.yaw)), si = std::abs(std::sin(robot.yaw));
  const double ex = co * robot.hx + si * robot.hy, ey = si * robot.hx + co * robot.hy;
  auto cell = [&](double v, double origin, int n) {
    return static_cast<int>(std::clamp(std::floor((v - origin) / m.resolution_m), 0.0, n - 1.0));
  };
  const int i0 = cell(robot.c.x - ex, m.origin_x_m, m.nx),
            i1 = cell(robot.c.x + ex, m.origin_x_m, m.nx);
  const int j0 = cell(robot.c.y - ey, m.origin_y_m, m.ny),
            j1 = cell(robot.c.y + ey, m.origin_y_m, m.ny);
  const double h = m.resolution_m / 2;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      if (map.cells[std::size_t(j) * std::size_t(m.nx) + std::size_t(i)] != fw::cost::kLethal) {
        continue;
      }
      const Vec2 c{m.origin_x_m + (i + 0.5) * m.resolution_m,
                   m.origin_y_m + (j + 0.5) * m.resolution_m};
      if (overlaps(robot, Obb{c, 0.0, h, h})) {
        where.expected(what, got + " (overlaps occupied cell (" + std::to_string(i) + ", " +
                                 std::to_string(j) + ") at x " + strict::format_number(c.x) +
                                 ", y " + strict::format_number(c.y) + " of " + map.image_path +
                                 ")");
      }
    }
  }
}

std::string rgb_text(Rgb c) {
  return "[" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + "]";
}

}  // namespace

// A pose the robot is put at (its start, a kidnap) must not be inside an obstacle or a wall (as
// SimWorld builds them: each wall segment a box of its length plus the thickness, thickness
// wide). `kind` names it in the message ("start", "kidnap").
void check_pose_clear(const Scenario& s, double x, double y, double yaw_rad, const Node& where,
                      const std::string& kind) {
  const RobotSpec& r = s.robot;
  const Obb robot{{x, y}, yaw_rad, r.length_m / 2, r.width_m / 2};
  const std::string what = "a " + kind + " pose whose " + r.preset + " footprint (" +
                           strict::format_number(r.length_m) + " x " +
                           strict::format_number(r.width_m) + " m) is clear of ";
  const std::string got = "x " + strict::format_number(x) + ", y " + strict::format_number(y) +
                          ", yaw_deg " + strict::format_number(yaw_rad * 180.0 / fw::kPi);
  for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
    const ObstacleSpec& o = s.obstacles[i];
    const bool hit = o.shape == ObstacleShape::Box
                         ? overlaps(robot, Obb{o.center, o.yaw_rad, o.size_x_m / 2, o.size_y_m / 2})
                         : overlaps(robot, o.center, o.radius_m);
    if (hit) {
      where.expected(what + "obstacles", got + " (overlaps obstacles[" + std::to_string(i) + "])");
    }
  }
  for (std::size_t i = 0; i < s.walls.size(); ++i) {
    const WallSpec& w = s.walls[i];
    for (std::size_t j = 0; j + 1 < w.points.size(); ++j) {
      const Vec2 a = w.points[j], b = w.points[j + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      if (len < 1e-6) continue;  // SimWorld builds nothing for it
      const Obb seg{{(a.x + b.x) / 2, (a.y + b.y) / 2},
                    std::atan2(b.y - a.y, b.x - a.x),
                    len / 2 + w.thickness_m / 2,
                    w.thickness_m / 2};
      if (overlaps(robot, seg)) {
        where.expected(what + "walls", got + " (overlaps walls[" + std::to_string(i) +
                                           "], segment " + std::to_string(j) + ")");
      }
    }
  }
  if (s.map) check_start_clear_of_map(robot, *s.map, where, what + "the map's occupied cells", got);
}

void check_start_clear(const Node& root, const Scenario& s) {
  const RobotSpec& r = s.robot;
  const Node robot_n = root.at("robot");
  const auto start = robot_n.get("start");
  const Node where = start ? *start : robot_n.child_path("start");
  check_pose_clear(s, r.start.x, r.start.y, r.start.yaw_rad, where, "start");
  // Where a kidnap sets the robot down is checked as its start is.
  if (auto loc = root.get("localisation")) {
    if (auto k = loc->get("kidnap")) {
      const auto items = k->items();
      for (std::size_t i = 0; i < items.size() && i < s.localisation.kidnaps.size(); ++i) {
        const auto& to = s.localisation.kidnaps[i].to;
        check_pose_clear(s, to.x, to.y, to.yaw_rad, items[i], "kidnap");
      }
    }
  }
}

// The detector must tell the tape and the end mark from the floor, and from each other.
void check_colours(const Node& root, const Scenario& s) {
  const Node mission = root.at("mission");
  const MissionSpec& m = s.mission;
  const fw::ColorThreshold line_t = detector_threshold(m.line_color_name, m.line_color);
  const fw::ColorThreshold end_t = detector_threshold(m.end_color_name, m.end_color);
  const std::string floor_text = "floor.color " + rgb_text(s.floor);
  auto floor_check = [&](const fw::ColorThreshold& t, const char* key, const std::string& name) {
    Rgb shade;
    double k = 1.0;
    if (!floor_shade_in(t, s.floor, s.floor_speckle, shade, k)) return;
    const auto n = mission.get(key);
    const Node where = n ? *n : mission.child_path(key);
    where.expected("a colour the detector tells from " + floor_text + " (its shade x" +
                       strict::format_number(k) + " = " + rgb_text(shade) + " is inside the " +
                       name + " window)",
                   name);
  };
  floor_check(line_t, "line_color", m.line_color_name);
  floor_check(end_t, "end_color", m.end_color_name);
  const bool line_as_end = detector_sees(end_t, m.line_color);
  const bool end_as_line = detector_sees(line_t, m.end_color);
  if (line_as_end || end_as_line) {
    const auto n = mission.get("end_color");
    const Node where = n ? *n : mission.child_path("end_color");
    where.expected("an end colour the detector tells from mission.line_color " + m.line_color_name +
                       " (" +
                       (line_as_end ? "the tape falls in the end window"
                                    : "the end colour falls in the tape window") +
                       ")",
                   m.end_color_name);
  }
}

}  // namespace carril::sim
