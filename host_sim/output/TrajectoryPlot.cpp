// trajectory.png: the scenario seen from above (y up) with the robot's path on it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgproc.hpp>

#include "host_sim/output/PlotUtil.hpp"
#include "host_sim/output/Plots.hpp"
#include "loader/OccupancyMapFile.hpp"

namespace carril::sim {
namespace {

constexpr int kMaxSidePx = 1200;
constexpr int kTitleBandPx = 54;
constexpr int kShift = 3;  // fractional bits of drawing coordinates (sub-pixel accuracy)
constexpr double kMarginM = 0.5;

const cv::Scalar kObstacle(70, 70, 70), kObstacleEdge(30, 30, 30), kWall(35, 35, 35);
const cv::Scalar kRamp(0, 140, 255), kStep(200, 0, 200), kCollision(0, 0, 255);
const cv::Scalar kStart(0, 190, 0), kBlack(0, 0, 0), kWhite(255, 255, 255);

// Path colours by behaviour state, in order of first appearance; red is kept for collisions.
const cv::Scalar kPalette[] = {{180, 119, 31},  {14, 127, 255},  {44, 160, 44},  {189, 103, 148},
                               {75, 86, 140},   {194, 119, 227}, {34, 189, 188}, {207, 190, 23},
                               {127, 127, 127}, {0, 0, 0}};

struct Bounds {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  void add(double x, double y, double pad = 0.0) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(pad)) return;
    x0 = std::min(x0, x - pad);
    x1 = std::max(x1, x + pad);
    y0 = std::min(y0, y - pad);
    y1 = std::max(y1, y + pad);
  }
  bool valid() const { return x0 <= x1 && y0 <= y1; }
};

// World metres -> image pixels (with kShift fractional bits), y up.
struct View {
  double x0 = 0.0, y1 = 0.0, scale = 1.0;  // left edge, top edge [m], [px/m]
  cv::Point px(double x, double y) const {
    const double f = 1 << kShift;
    return {static_cast<int>(std::lround((x - x0) * scale * f)),
            static_cast<int>(std::lround((kTitleBandPx + (y1 - y) * scale) * f))};
  }
  cv::Point px(Vec2 v) const { return px(v.x, v.y); }
  cv::Point whole(double x, double y) const {  // integer pixels, for text
    const cv::Point p = px(x, y);
    return {p.x >> kShift, p.y >> kShift};
  }
  int len(double m, int min_px) const {  // a length in whole pixels, at least min_px
    const double v = m * scale;
    return std::isfinite(v) ? std::clamp(static_cast<int>(std::lround(v)), min_px, 4000) : min_px;
  }
};

// Corners of a rectangle centred at c, rotated by yaw.
std::vector<Vec2> rect_corners(Vec2 c, double yaw, double lx, double ly) {
  const double cs = std::cos(yaw), sn = std::sin(yaw);
  std::vector<Vec2> out;
  for (const auto& [u, v] : {std::pair{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}) {
    const double dx = u * lx / 2.0, dy = v * ly / 2.0;
    out.push_back({c.x + cs * dx - sn * dy, c.y + sn * dx + cs * dy});
  }
  return out;
}

bool finite(const TrajectoryRow& r) {
  return std::isfinite(r.x) && std::isfinite(r.y);
}
bool finite(Vec2 p) {
  return std::isfinite(p.x) && std::isfinite(p.y);
}

Bounds scene_bounds(const Scenario& sc, const std::vector<TrajectoryRow>& rows,
                    const std::vector<CollisionPoint>& collisions) {
  Bounds b;
  for (const LineSpec& l : sc.lines)
    for (const Vec2& p : l.points) b.add(p.x, p.y, l.width_m / 2.0);
  for (const MarkSpec& m : sc.marks) b.add(m.center.x, m.center.y, m.radius_m);
  for (const ObstacleSpec& o : sc.obstacles) {
    if (o.shape == ObstacleShape::Cylinder) {
      b.add(o.center.x, o.center.y, o.radius_m);
    } else {
      for (const Vec2& c : rect_corners(o.center, o.yaw_rad, o.size_x_m, o.size_y_m))
        b.add(c.x, c.y);
    }
  }
  for (const WallSpec& w : sc.walls)
    for (const Vec2& p : w.points) b.add(p.x, p.y, w.thickness_m / 2.0);
  if (sc.map) {
    const fw::MapInfo& m = sc.map->info;
    b.add(m.origin_x_m, m.origin_y_m);
    b.add(m.origin_x_m + m.nx * m.resolution_m, m.origin_y_m + m.ny * m.resolution_m);
  }
  for (const TerrainSpec& t : sc.terrain)
    for (const Vec2& c : rect_corners(t.center, t.yaw_rad, t.length_m, t.width_m)) b.add(c.x, c.y);
  for (const TrajectoryRow& r : rows) b.add(r.x, r.y);
  for (const CollisionPoint& c : collisions) b.add(c.x, c.y);
  b.add(sc.robot.start.x, sc.robot.start.y, 0.3);
  if (!b.valid()) b.add(0.0, 0.0, 1.0);
  return b;
}

void draw_x(cv::Mat& img, cv::Point c, int r, cv::Scalar color) {
  const int d = r << kShift;
  cv::line(img, c + cv::Point(-d, -d), c + cv::Point(d, d), color, 2, cv::LINE_AA, kShift);
  cv::line(img, c + cv::Point(-d, d), c + cv::Point(d, -d), color, 2, cv::LINE_AA, kShift);
}

void draw_scene(cv::Mat& img, const View& v, const Scenario& sc) {
  auto poly = [&](const std::vector<Vec2>& pts) {
    std::vector<cv::Point> out;
    for (const Vec2& p : pts) {
      if (finite(p)) out.push_back(v.px(p));  // never round a NaN to int: it traps
    }
    return out;
  };
  // Terrain first: an outline under everything else; ramp and step differ in colour and label.
  for (const TerrainSpec& t : sc.terrain) {
    const bool ramp = t.type == TerrainType::Ramp;
    const auto corners = poly(rect_corners(t.center, t.yaw_rad, t.length_m, t.width_m));
    cv::polylines(img, corners, true, ramp ? kRamp : kStep, 2, cv::LINE_AA, kShift);
    if (!ramp) {  // a step's outline is doubled
      const auto inner = poly(rect_corners(t.center, t.yaw_rad, t.length_m * 0.9, t.width_m * 0.9));
      cv::polylines(img, inner, true, kStep, 1, cv::LINE_AA, kShift);
    }
    char label[64];
    if (ramp) {
      std::snprintf(label, sizeof label, "ramp %.0f deg", t.angle_deg);
    } else {
      std::snprintf(label, sizeof label, "step %.2f m", t.height_m);
    }
    if (finite(t.center)) {
      int baseline = 0;
      const int tw = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline).width;
      plot::put_text(img, label, v.whole(t.center.x, t.center.y) + cv::Point(-tw / 2, 5), 0.45,
                     ramp ? kRamp : kStep);
    }
  }
  // A map's occupied cells, as walls (whole cells, filled).
  if (sc.map) {
    const fw::MapInfo& m = sc.map->info;
    const double r = m.resolution_m;
    for (int j = 0; j < m.ny; ++j) {
      for (int i = 0; i < m.nx; ++i) {
        if (sc.map->cells[std::size_t(j) * std::size_t(m.nx) + std::size_t(i)] != 254) continue;
        const double x = m.origin_x_m + i * r, y = m.origin_y_m + j * r;
        cv::rectangle(img, v.px(x, y + r), v.px(x + r, y), kWall, cv::FILLED, cv::LINE_8, kShift);
      }
    }
  }
  // Walls: filled strips of their real thickness, joints rounded.
  for (const WallSpec& w : sc.walls) {
    const int th = v.len(w.thickness_m, 1);
    for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
      if (!finite(w.points[i]) || !finite(w.points[i + 1])) continue;
      cv::line(img, v.px(w.points[i]), v.px(w.points[i + 1]), kWall, th, cv::LINE_AA, kShift);
    }
  }
  // Tape at its real width (at least 1 px), in its own colour.
  for (const LineSpec& l : sc.lines) {
    if (l.points.size() < 2) continue;
    cv::polylines(img, poly(l.points), false, plot::bgr(l.color), v.len(l.width_m, 1), cv::LINE_AA,
                  kShift);
  }
  for (const MarkSpec& m : sc.marks) {
    if (!finite(m.center)) continue;
    cv::circle(img, v.px(m.center), v.len(m.radius_m, 1) << kShift, plot::bgr(m.color), cv::FILLED,
               cv::LINE_AA, kShift);
  }
  for (const ObstacleSpec& o : sc.obstacles) {
    if (!finite(o.center)) continue;
    if (o.shape == ObstacleShape::Cylinder) {
      const int r = v.len(o.radius_m, 1) << kShift;
      cv::circle(img, v.px(o.center), r, kObstacle, cv::FILLED, cv::LINE_AA, kShift);
      cv::circle(img, v.px(o.center), r, kObstacleEdge, 1, cv::LINE_AA, kShift);
    } else {
      const auto corners = poly(rect_corners(o.center, o.yaw_rad, o.size_x_m, o.size_y_m));
      cv::fillConvexPoly(img, corners, kObstacle, cv::LINE_AA, kShift);
      cv::polylines(img, corners, true, kObstacleEdge, 1, cv::LINE_AA, kShift);
    }
  }
}

// Draws the path by state; returns the state names in legend order.
std::vector<std::string> draw_path(cv::Mat& img, const View& v,
                                   const std::vector<TrajectoryRow>& rows) {
  std::vector<std::string> names;
  std::map<std::string, std::size_t> index;
  auto color_of = [&](const char* state) {
    std::string name = state != nullptr && state[0] != '\0' ? state : "(none)";
    auto [it, added] = index.try_emplace(name, names.size());
    if (added) names.push_back(name);
    return it->second;
  };
  const std::size_t n_palette = std::size(kPalette);
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    const std::size_t c = color_of(rows[i].state);
    if (!finite(rows[i]) || !finite(rows[i + 1])) continue;
    cv::line(img, v.px(rows[i].x, rows[i].y), v.px(rows[i + 1].x, rows[i + 1].y),
             kPalette[c % n_palette], 2, cv::LINE_AA, kShift);
  }
  if (rows.size() == 1) color_of(rows[0].state);
  return names;
}

void draw_legend(cv::Mat& img, const std::vector<std::string>& states, bool collisions) {
  const int row_h = 18, x = 10, y = kTitleBandPx + 10;
  const int rows = static_cast<int>(states.size()) + 1 + (collisions ? 1 : 0);
  int width = 110;
  for (const std::string& s : states) {
    int baseline = 0;
    width = std::max(
        width,
        40 + cv::getTextSize(plot::ascii(s), cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline).width);
  }
  plot::shade_rect(img, cv::Rect(x, y, width, rows * row_h + 8), kWhite, 0.8);
  int yy = y + 4 + row_h / 2;
  const std::size_t n_palette = std::size(kPalette);
  for (std::size_t i = 0; i < states.size(); ++i, yy += row_h) {
    cv::line(img, {x + 6, yy}, {x + 28, yy}, kPalette[i % n_palette], 3, cv::LINE_AA);
    plot::put_text(img, states[i], {x + 34, yy + 5}, 0.45, kBlack);
  }
  const std::vector<cv::Point> tri = {{x + 24, yy}, {x + 11, yy - 6}, {x + 11, yy + 6}};
  cv::fillConvexPoly(img, tri, kStart, cv::LINE_AA);
  cv::polylines(img, tri, true, kBlack, 1, cv::LINE_AA);
  plot::put_text(img, "start", {x + 34, yy + 5}, 0.45, kBlack);
  yy += row_h;
  if (collisions) {
    draw_x(img, cv::Point(x + 17, yy) * (1 << kShift), 5, kCollision);
    plot::put_text(img, "collision", {x + 34, yy + 5}, 0.45, kBlack);
  }
}

void draw_scale_bar(cv::Mat& img, const View& v) {
  const int len = v.len(1.0, 1);
  const int x = 14, y = img.rows - 16;
  plot::shade_rect(img, cv::Rect(x - 6, y - 22, len + 50, 32), kWhite, 0.8);
  cv::line(img, {x, y}, {x + len, y}, kBlack, 2);
  cv::line(img, {x, y - 5}, {x, y + 5}, kBlack, 2);
  cv::line(img, {x + len, y - 5}, {x + len, y + 5}, kBlack, 2);
  plot::put_text(img, "1 m", {x + len / 2 - 10, y - 8}, 0.45, kBlack);
}

void draw_title(cv::Mat& img, const RunSummary& s) {
  cv::rectangle(img, cv::Rect(0, 0, img.cols, kTitleBandPx), cv::Scalar(245, 245, 245), cv::FILLED);
  cv::line(img, {0, kTitleBandPx - 1}, {img.cols, kTitleBandPx - 1}, cv::Scalar(180, 180, 180), 1);
  const std::string line1 = s.scenario + "  -  " + s.result + (s.passed ? "  (PASS)" : "  (FAIL)");
  char line2[256];
  std::snprintf(line2, sizeof line2,
                "progress %.2f   laps %d   cross-track rms %.3f m   collisions %d   sim %.1f s   "
                "path %.1f m",
                s.progress, s.laps, s.cross_track_rms_m, s.collisions, s.sim_time_s,
                s.path_length_m);
  plot::put_text(img, line1, {10, 22}, 0.6, kBlack, img.cols - 20, 1);
  plot::put_text(img, line2, {10, 44}, 0.45, cv::Scalar(60, 60, 60), img.cols - 20, 1);
}

}  // namespace

bool render_trajectory_png(const Scenario& scenario, const std::vector<TrajectoryRow>& rows,
                           const std::vector<CollisionPoint>& collisions, const RunSummary& summary,
                           std::string& png, std::string& error) {
  Bounds b = scene_bounds(scenario, rows, collisions);
  b.x0 -= kMarginM;
  b.y0 -= kMarginM;
  b.x1 += kMarginM;
  b.y1 += kMarginM;
  // Widen the shorter side so that the title, legend and scale bar have room.
  double w = b.x1 - b.x0, h = b.y1 - b.y0;
  if (w < 0.6 * h) {
    b.x0 -= (0.6 * h - w) / 2.0;
    w = 0.6 * h;
  }
  if (h < 0.35 * w) {
    b.y0 -= (0.35 * w - h) / 2.0;
    h = 0.35 * w;
  }
  View v;
  v.x0 = b.x0;
  v.y1 = b.y0 + h;
  v.scale = std::min(kMaxSidePx / w, (kMaxSidePx - kTitleBandPx) / h);
  const int cols = std::clamp(static_cast<int>(std::lround(w * v.scale)), 1, kMaxSidePx);
  const int img_rows =
      std::clamp(static_cast<int>(std::lround(h * v.scale)) + kTitleBandPx, 1, kMaxSidePx);

  cv::Mat img(img_rows, cols, CV_8UC3, plot::bgr(scenario.floor));
  draw_scene(img, v, scenario);
  const std::vector<std::string> states = draw_path(img, v, rows);
  for (const CollisionPoint& c : collisions) {
    if (std::isfinite(c.x) && std::isfinite(c.y)) draw_x(img, v.px(c.x, c.y), 7, kCollision);
  }
  // Start: a triangle pointing along the start heading.
  const Pose2& st = scenario.robot.start;
  if (std::isfinite(st.x) && std::isfinite(st.y) && std::isfinite(st.yaw_rad)) {
    const double r = 12.0 / v.scale, cs = std::cos(st.yaw_rad), sn = std::sin(st.yaw_rad);
    const std::vector<cv::Point> tri = {
        v.px(st.x + cs * r, st.y + sn * r),
        v.px(st.x - cs * r * 0.6 - sn * r * 0.6, st.y - sn * r * 0.6 + cs * r * 0.6),
        v.px(st.x - cs * r * 0.6 + sn * r * 0.6, st.y - sn * r * 0.6 - cs * r * 0.6)};
    cv::fillConvexPoly(img, tri, kStart, cv::LINE_AA, kShift);
    cv::polylines(img, tri, true, kBlack, 1, cv::LINE_AA, kShift);
  }
  draw_legend(img, states, !collisions.empty());
  draw_scale_bar(img, v);
  draw_title(img, summary);
  return plot::encode_png(img, png, error);
}

}  // namespace carril::sim
