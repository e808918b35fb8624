#include "host_sim/app/CostmapOutputs.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "loader/CostmapExport.hpp"
#include "loader/CostmapPng.hpp"
#include "loader/ElevationMapFile.hpp"

namespace carril::sim {

namespace {
using fw::kPi;  // the one pi, firmware/core/Geometry.hpp

const char* label_name(CellLabel l) {
  switch (l) {
    case CellLabel::Free:
      return "free";
    case CellLabel::Passable:
      return "passable";
    case CellLabel::Lethal:
      return "lethal";
    case CellLabel::Unknown:
      return "unknown";
  }
  return "?";
}

bool label_holds(CellLabel l, std::uint8_t c) {
  switch (l) {
    case CellLabel::Free:  // the thesis's "free": traversable, whatever its graded cost
    case CellLabel::Passable:
      return fw::cost::passable(c);
    case CellLabel::Lethal:
      return c == fw::cost::kLethal;
    case CellLabel::Unknown:
      return c == fw::cost::kUnknown;
  }
  return false;
}

const fw::RollingGrid<std::uint8_t>* layer_of(const fw::Firmware& f, CellLayer l) {
  const fw::Mapping& m = f.mapping;
  if (!m.enabled()) return nullptr;
  switch (l) {
    case CellLayer::Master:
      return &m.master();
    case CellLayer::Obstacle:
      return &m.costmap().obstacle_layer();
    case CellLayer::Traversability:
      return m.config().terrain ? &m.traversability().grid() : nullptr;
  }
  return nullptr;
}

std::vector<std::uint8_t> window_of(const fw::RollingGrid<std::uint8_t>& g) {
  std::vector<std::uint8_t> out(std::size_t(g.nx()) * std::size_t(g.ny()));
  g.copy_to(out.data());
  return out;
}

loader::CostmapGeometry geometry_of(const fw::RollingGrid<std::uint8_t>& g) {
  return {std::uint32_t(g.nx()), std::uint32_t(g.ny()), g.resolution(), g.origin_x(), g.origin_y()};
}
}  // namespace

fw::Pose2 world_to_odom(const Pose2& start, double x, double y, double yaw_rad) {
  const double c = std::cos(start.yaw_rad), s = std::sin(start.yaw_rad);
  const double dx = x - start.x, dy = y - start.y;
  return {c * dx + s * dy, -s * dx + c * dy, fw::wrap_angle(yaw_rad - start.yaw_rad)};
}

void score_goto(const Scenario& s, const fw::Firmware& firmware, const Pose2& p, RunSummary& r) {
  if (s.mission.type != "goto") return;
  const double gyaw = s.mission.goal_yaw_deg * kPi / 180.0;
  r.goal_error_m = std::hypot(p.x - s.mission.goal_x_m, p.y - s.mission.goal_y_m);
  r.goal_yaw_error_deg = std::fabs(fw::wrap_angle(p.yaw_rad - gyaw)) * 180.0 / kPi;
  r.goal_reached = firmware.goto_mission.current() == fw::GotoMission::State::Done &&
                   *r.goal_error_m <= 0.1 && *r.goal_yaw_error_deg <= 10.0;
  r.replans = long(firmware.goto_mission.replans());
}

void check_cells(const Scenario& s, const fw::Firmware& f, RunSummary& r) {
  for (const CellExpect& c : s.expect.cells) {
    const fw::RollingGrid<std::uint8_t>* g = layer_of(f, c.layer);
    char buf[256];
    if (g == nullptr) {
      std::snprintf(buf, sizeof buf, "cells: (%.2f, %.2f) %s: the firmware builds no such layer",
                    c.at.x, c.at.y, c.what.c_str());
      r.unmet_expectations.emplace_back(buf);
      continue;
    }
    const fw::Pose2 o = world_to_odom(s.robot.start, c.at.x, c.at.y, 0.0);
    int cx = 0, cy = 0;
    const bool inside = g->world_to_cell(o.x, o.y, cx, cy);
    std::uint8_t cost = inside ? g->at(cx, cy) : fw::cost::kUnknown;
    // An edge (a step, a face) is one cell wide and which cell holds it depends on where the
    // edge falls in the grid: lethal is met by the cell or one of its 8 neighbours.
    if (inside && c.label == CellLabel::Lethal && cost != fw::cost::kLethal) {
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (g->contains(cx + dx, cy + dy) && g->at(cx + dx, cy + dy) == fw::cost::kLethal)
            cost = fw::cost::kLethal;
    }
    ++r.cells_checked;
    if (!label_holds(c.label, cost)) {
      std::snprintf(buf, sizeof buf, "cells: (%.2f, %.2f) %s: expected %s, got cost %u%s", c.at.x,
                    c.at.y, c.what.c_str(), label_name(c.label), unsigned(cost),
                    inside ? "" : " (outside the costmap)");
      r.unmet_expectations.emplace_back(buf);
    }
  }
}

bool write_costmap_outputs(const fw::Firmware& f, const std::string& dir, std::string& error,
                           bool pngs) {
  const fw::Mapping& m = f.mapping;
  if (!m.enabled()) return true;
  auto png = [&](const fw::RollingGrid<std::uint8_t>& g, const char* name) {
    if (!pngs) return true;
    const std::vector<std::uint8_t> w = window_of(g);
    if (auto e = loader::export_costmap_png(dir + "/" + name, w.data(), geometry_of(g), 2)) {
      error = *e;
      return false;
    }
    return true;
  };
  if (!png(m.master(), "costmap.png") || !png(m.costmap().obstacle_layer(), "obstacles.png")) {
    return false;
  }
  const std::vector<std::uint8_t> w = window_of(m.master());
  if (auto e = loader::export_costmap_pgm(dir + "/costmap", w.data(), geometry_of(m.master()))) {
    error = *e;
    return false;
  }
  if (!m.config().terrain) return true;
  if (!png(m.traversability().grid(), "traversability.png")) return false;
  const fw::RollingGrid<fw::ElevationCell>& e = m.elevation().grid();
  loader::ElevationMapData map;
  map.resolution_m = e.resolution();
  map.nx = std::uint32_t(e.nx());
  map.ny = std::uint32_t(e.ny());
  map.origin_x_m = e.origin_x();
  map.origin_y_m = e.origin_y();
  map.frame = "odom";
  map.cells.resize(std::size_t(e.nx()) * std::size_t(e.ny()));
  e.copy_to(map.cells.data());
  if (auto err = loader::save_elevation_map(dir + "/elevation.cmap", map)) {
    error = *err;
    return false;
  }
  return true;
}

}  // namespace carril::sim
