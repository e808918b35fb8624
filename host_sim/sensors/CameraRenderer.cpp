#include "host_sim/sensors/CameraRenderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "host_sim/scenario/ColorCheck.hpp"
#include "host_sim/scenario/HypotScreen.hpp"
#include "host_sim/sensors/ConvexFill.hpp"
#include "host_sim/sensors/Normal.hpp"
#include "host_sim/sensors/SaturatingAdd.hpp"
#include "host_sim/sensors/TapeWear.hpp"

namespace carril::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr double kNearZ = 0.02;        // clip polygons this close to the camera plane [m]
constexpr double kSpeckleCell = 0.25;  // floor texture: one speckle per cell this size [m]
constexpr double kTextureRange = 6.0;  // no texture beyond this from the camera (sub-pixel) [m]
// A polygon this far outside the image sets no pixel (fills round to the nearest pixel; the
// equality test fails at 0 and passes at 0.6) [px].
constexpr double kViewMarginPx = 2.0;
constexpr double kSpeckleRadius = 1.41422;  // a speckle's bounding radius over its half-size
constexpr double kSlack = 1e-6;  // tolerance on cell and region bounds, far above rounding [m]

// The cells of the world box round the robot-frame box [x0, x1] x [-y, y] seen from `pose`.
struct CellBox {
  std::int64_t i0, i1, j0, j1;
};
CellBox texture_cells(const Pose2& pose, double bx0, double bx1, double by) {
  const double co = std::cos(pose.yaw_rad), si = std::sin(pose.yaw_rad);
  double x0 = 1e18, x1 = -1e18, y0 = 1e18, y1 = -1e18;
  for (double rx : {bx0, bx1}) {
    for (double ry : {-by, by}) {
      const double wx = pose.x + co * rx - si * ry, wy = pose.y + si * rx + co * ry;
      x0 = std::min(x0, wx);
      x1 = std::max(x1, wx);
      y0 = std::min(y0, wy);
      y1 = std::max(y1, wy);
    }
  }
  return {std::int64_t(std::floor(x0 / kSpeckleCell)), std::int64_t(std::floor(x1 / kSpeckleCell)),
          std::int64_t(std::floor(y0 / kSpeckleCell)), std::int64_t(std::floor(y1 / kSpeckleCell))};
}

// Cuts convex polygon `pts` to the side where a*x + b*y + c >= 0 (Sutherland-Hodgman).
std::vector<Vec2> cut(const std::vector<Vec2>& pts, double a, double b, double c) {
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2 p = pts[i], q = pts[(i + 1) % pts.size()];
    const double gp = a * p.x + b * p.y + c, gq = a * q.x + b * q.y + c;
    if (gp >= 0) out.push_back(p);
    if ((gp >= 0) != (gq >= 0)) {
      const double t = gp / (gp - gq);
      out.push_back({p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t});
    }
  }
  return out;
}

// 64-bit mix of a floor cell's integer coordinates (splitmix64 finaliser).
std::uint64_t cell_hash(std::int64_t i, std::int64_t j) {
  std::uint64_t z =
      std::uint64_t(i) * 0x9E3779B97F4A7C15ULL ^ std::uint64_t(j) * 0xC2B2AE3D27D4EB4FULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Uniform in [0, 1) from 16 bits of h starting at bit `at`.
double unit(std::uint64_t h, int at) {
  return double((h >> at) & 0xFFFF) / 65536.0;
}

std::vector<Vec2> disk(Vec2 c, double r, int n) {
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    pts.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  return pts;
}

std::vector<Vec2> rect(Vec2 c, double yaw, double hx, double hy) {
  const double co = std::cos(yaw), si = std::sin(yaw);
  std::vector<Vec2> pts;
  for (auto [sx, sy] : {std::pair{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}) {
    pts.push_back({c.x + co * sx * hx - si * sy * hy, c.y + si * sx * hx + co * sy * hy});
  }
  return pts;
}
}  // namespace

CameraRenderer::CameraRenderer(const Scenario& scenario, std::uint64_t seed)
    : scenario_(scenario),
      cam_(camera_mount(scenario.robot.camera)),
      noise_std_(scenario.robot.camera.noise_std),
      rng_(seed ^ 0xCA3E4A11ULL),
      effects_(scenario, seed) {
  const std::vector<std::vector<TapeGap>> gaps = tape_gaps(scenario, seed);
  for (std::size_t k = 0; k < scenario.lines.size(); ++k) {
    const LineSpec& line = scenario.lines[k];
    const Rgb color = faded(line.color, scenario.floor, scenario.tape_wear.fade);
    for (const std::vector<Vec2>& points : tape_pieces(line.points, gaps[k])) {
      add_tape(points, line.width_m, color);
    }
  }
  for (const MarkSpec& m : scenario.marks) add_poly(disk(m.center, m.radius_m, 48), m.color);
  const Rgb obstacle_base{40, 40, 45};
  for (const ObstacleSpec& o : scenario.obstacles) {
    if (o.shape == ObstacleShape::Box) {
      add_poly(rect(o.center, o.yaw_rad, o.size_x_m / 2, o.size_y_m / 2), obstacle_base);
    } else {
      add_poly(disk(o.center, o.radius_m, 32), obstacle_base);
    }
  }
  // Nothing beyond the far corner of the image footprint can be visible; 3x covers tilts near
  // the horizon while keeping the cull useful.
  const CameraSpec& cs = scenario.robot.camera;
  const double far_angle =
      std::max(cs.tilt_deg * kDeg - std::atan2(cs.height / 2.0, cam_.fx()), 0.05);
  view_radius_m_ = std::min(3.0 * cs.z_m / std::tan(far_angle) + 1.0, 30.0);
  // The floor the image can show, as a robot-frame box: the image border's floor points, those
  // beyond the texture range (or above the horizon) cut at that range.
  const double reach = std::min(view_radius_m_, kTextureRange);
  texture_x0_ = 1e9;
  texture_x1_ = -1e9;
  texture_y_ = 0.0;
  const Vec2 cam_xy{cs.x_m, cs.y_m};
  for (int k = 0; k <= 64; ++k) {
    const double a = k / 64.0;
    const fw::Vec2 border[4] = {{a * (cs.width - 1), 0.0},
                                {a * (cs.width - 1), cs.height - 1.0},
                                {0.0, a * (cs.height - 1)},
                                {cs.width - 1.0, a * (cs.height - 1)}};
    for (const fw::Vec2& px : border) {
      fw::Vec2 f;
      bool ok = cam_.pixel_to_floor(px, f);
      if (ok) {
        const double dx = f.x() - cam_xy.x, dy = f.y() - cam_xy.y, d = std::hypot(dx, dy);
        if (d > reach) f = fw::Vec2(cam_xy.x + dx * reach / d, cam_xy.y + dy * reach / d);
      } else {
        f = fw::Vec2(cam_xy.x + reach, 0.0);  // above the horizon: the floor runs out to reach
        texture_y_ = std::max(texture_y_, reach);
      }
      texture_x0_ = std::min(texture_x0_, f.x());
      texture_x1_ = std::max(texture_x1_, f.x());
      texture_y_ = std::max(texture_y_, std::fabs(f.y()));
    }
  }
  // The floor half-planes that can reach the image, from camera-frame forms k . (x, y, z) + k3:
  // a floor point maps affinely to the camera frame, so each is a half-plane of the floor.
  const fw::Vec3 q0 = cam_.to_camera(fw::Vec3(0, 0, 0));
  const fw::Vec3 qx = cam_.to_camera(fw::Vec3(1, 0, 0)) - q0;
  const fw::Vec3 qy = cam_.to_camera(fw::Vec3(0, 1, 0)) - q0;
  const double fl = cam_.fx(), m = kViewMarginPx;
  const double forms[5][4] = {{0, 0, 1, -kNearZ},                           // z >= near plane
                              {fl, 0, cam_.cx() + m, 0},                    // u >= -m
                              {-fl, 0, cs.width - 1 + m - cam_.cx(), 0},    // u <= width - 1 + m
                              {0, fl, cam_.cy() + m, 0},                    // v >= -m
                              {0, -fl, cs.height - 1 + m - cam_.cy(), 0}};  // v <= height - 1 + m
  for (const auto& k : forms) {
    const double a = k[0] * qx.x() + k[1] * qx.y() + k[2] * qx.z();
    const double b = k[0] * qy.x() + k[1] * qy.y() + k[2] * qy.z();
    const double c = k[0] * q0.x() + k[1] * q0.y() + k[2] * q0.z() + k[3];
    const double n = std::hypot(a, b);
    if (n > 1e-12) {
      view_.push_back({a / n, b / n, c / n});
    } else if (c < 0) {
      view_.push_back({0.0, 0.0, -1.0});  // the whole floor is on the wrong side
    }
  }
  texture_region_ = {{texture_x0_ - 0.1, -texture_y_ - 0.1},
                     {texture_x1_ + 0.1, -texture_y_ - 0.1},
                     {texture_x1_ + 0.1, texture_y_ + 0.1},
                     {texture_x0_ - 0.1, texture_y_ + 0.1}};
  const double reach_out = 0.05 * kSpeckleRadius + kSlack;  // the largest speckle's radius
  for (const HalfPlane& h : view_)
    texture_region_ = cut(texture_region_, h.a, h.b, h.c + reach_out);
  if (noise_std_ > 0) {
    // A table of noise samples, read from a random offset each frame: per-pixel Gaussian draws
    // would cost more than the rest of the simulation together.
    // Each sample as its positive and its negative part, for saturating byte arithmetic.
    const Normal n(0.0, noise_std_);
    noise_up_.resize(1 << 20);
    noise_down_.resize(1 << 20);
    for (std::size_t i = 0; i < noise_up_.size(); ++i) {
      const long v = std::lround(std::clamp(n(rng_), -255.0, 255.0));
      noise_up_[i] = static_cast<std::uint8_t>(v > 0 ? v : 0);
      noise_down_[i] = static_cast<std::uint8_t>(v < 0 ? -v : 0);
    }
  }
}

void CameraRenderer::add_tape(const std::vector<Vec2>& pts, double width_m, Rgb color) {
  const double h = width_m / 2;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec2 a = pts[i], b = pts[i + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len < 1e-9) continue;
    const double nx = -(b.y - a.y) / len * h, ny = (b.x - a.x) / len * h;
    add_poly(
        {{a.x + nx, a.y + ny}, {b.x + nx, b.y + ny}, {b.x - nx, b.y - ny}, {a.x - nx, a.y - ny}},
        color);
    // Round joins, so corners have no notch (only where the direction changes noticeably).
    if (i + 2 < pts.size()) {
      const Vec2 c = pts[i + 2];
      const double cross = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
      const double len2 = std::hypot(c.x - b.x, c.y - b.y);
      if (len2 > 1e-9 && std::fabs(cross / (len * len2)) > 0.05) add_poly(disk(b, h, 16), color);
    }
  }
}

void CameraRenderer::add_poly(std::vector<Vec2> pts, Rgb color) {
  double cx = 0, cy = 0;
  for (const Vec2& p : pts) {
    cx += p.x;
    cy += p.y;
  }
  cx /= double(pts.size());
  cy /= double(pts.size());
  double r = 0;
  for (const Vec2& p : pts) r = std::max(r, std::hypot(p.x - cx, p.y - cy));
  polys_.push_back({std::move(pts), color, cx, cy, r});
}

void CameraRenderer::render(const Pose2& pose, hal::CameraFrame& frame, bool as_rendered) {
  const CameraSpec& cs = scenario_.robot.camera;
  frame.width = static_cast<std::uint16_t>(cs.width);
  frame.height = static_cast<std::uint16_t>(cs.height);
  cv::Mat img(cs.height, cs.width, CV_8UC3, frame.bgr.data());
  const Rgb f = effects_.expose(scenario_.floor);
  const bool same_floor = f.r == drawn_floor_.r && f.g == drawn_floor_.g && f.b == drawn_floor_.b;
  if (reference_) {
    img.setTo(cv::Scalar(f.b, f.g, f.r));
  } else if (as_rendered && drawn_frame_ == frame.bgr.data() && same_floor) {
    unfill(f, img);  // 18 to 21 % of the pixels on the thesis courses, not all of them
    ++unfills_;
  } else {
    fill_floor(f, img);
  }
  // What this frame draws is kept for the next unless noise will touch every pixel.
  keep_drawn_ = !reference_ && noise_std_ <= 0;
  drawn_.clear();
  drawn_pts_.clear();
  drawn_frame_ = keep_drawn_ ? frame.bgr.data() : nullptr;
  drawn_floor_ = f;

  const double co = std::cos(pose.yaw_rad), si = std::sin(pose.yaw_rad);
  const double cam_wx = pose.x + co * cs.x_m - si * cs.y_m;
  const double cam_wy = pose.y + si * cs.x_m + co * cs.y_m;
  if (reference_) {
    draw_texture_reference(pose, img);
  } else {
    draw_texture(pose, img);
  }
  for (const Poly& poly : polys_) {
    if (!hypot_at_most(poly.cx - cam_wx, poly.cy - cam_wy, view_radius_m_ + poly.r)) continue;
    if (!reference_) {
      // A polygon wholly outside one of the image's floor half-planes sets no pixel (as for the
      // speckles); the reference path draws it and the tests compare the two.
      const double dx = poly.cx - pose.x, dy = poly.cy - pose.y;
      if (!may_show(co * dx + si * dy, -si * dx + co * dy, poly.r)) continue;
    }
    draw(poly.pts, poly.color, pose, co, si, img);
  }

  // Exposure went into the colours drawn (draw()); the glare goes on top.
  int u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  if (keep_drawn_ && effects_.glare_box(frames_, cs.width, cs.height, u0, u1, v0, v1)) {
    drawn_.push_back({0, 0, u0, v0, u1, v1});
  }
  effects_.apply_glare(frame, frames_);
  ++frames_;
  if (noise_std_ > 0) {
    const std::size_t n = std::size_t(cs.width) * cs.height * 3;
    const std::size_t size = noise_up_.size();
    std::size_t k = std::uniform_int_distribution<std::size_t>(0, size - 1)(rng_);
    std::uint8_t* d = frame.bgr.data();
    // In runs that do not wrap round the table: clamp(level + sample, 0, 255) per byte.
    for (std::size_t i = 0; i < n;) {
      const std::size_t m = std::min(n - i, size - k);
      add_sub_saturate(d + i, noise_up_.data() + k, noise_down_.data() + k, m);
      i += m;
      k = 0;
    }
  }
}

namespace {
// Bytes of one pattern block: a whole number of pixels (3 bytes) and of 64-byte stores.
constexpr std::size_t kPatternBytes = 192;
using Block64 = std::uint8_t __attribute__((vector_size(64), aligned(1)));

// The fill is bound by its stores: on x86-64 one clone per instruction set, picked when the
// program loads, so a block goes out in one AVX-512 store, two AVX2 stores or four SSE2 stores
// (1.5x faster from SSE2 to AVX-512 on this host). The same bytes whichever clone runs.
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void fill_pattern(std::uint8_t* d, std::size_t n, const std::uint8_t* pat) {
  Block64 v[kPatternBytes / 64];
  static_assert(sizeof v == kPatternBytes, "the pattern as whole 64-byte blocks");
  std::memcpy(&v, pat, sizeof v);
  std::size_t i = 0;
  for (; i + kPatternBytes <= n; i += kPatternBytes) {
    std::memcpy(d + i, &v[0], 64);
    std::memcpy(d + i + 64, &v[1], 64);
    std::memcpy(d + i + 128, &v[2], 64);
  }
  for (; i < n; ++i) d[i] = pat[i % kPatternBytes];
}
}  // namespace

void CameraRenderer::fill_floor(Rgb c, cv::Mat& img) {
  // The image wraps the frame's own buffer, so it is continuous: B, G, R repeated.
  std::uint8_t pat[kPatternBytes];
  for (std::size_t k = 0; k < kPatternBytes; k += 3) {
    pat[k] = c.b;
    pat[k + 1] = c.g;
    pat[k + 2] = c.r;
  }
  fill_pattern(img.data, img.total() * 3, pat);
}

void CameraRenderer::unfill(Rgb c, cv::Mat& img) const {
  // A polygon whose box is small (a floor speckle) gets its box filled; a large one (tape,
  // obstacles) is filled again in the floor colour, the same pixels as when it was drawn.
  constexpr long kBoxFillMaxPx = 4096;
  for (const Drawn& d : drawn_) {
    const long area = long(d.x1 - d.x0 + 1) * long(d.y1 - d.y0 + 1);
    if (d.n == 0 || area <= kBoxFillMaxPx) {
      fill_rect(img.data, img.cols, img.rows, d.x0, d.y0, d.x1, d.y1, c.b, c.g, c.r);
    } else {
      fill_convex_poly(img.data, img.cols, img.rows, drawn_pts_.data() + d.first, int(d.n), c.b,
                       c.g, c.r);
    }
  }
}

bool CameraRenderer::may_show(double x, double y, double r) const {
  // Wholly on the wrong side of one half-plane: every point of the disc (and of any part of it
  // clipped at the near plane) is behind the camera or projects 2 px or more outside the image.
  for (const HalfPlane& h : view_) {
    if (h.a * x + h.b * y + h.c + r < -kSlack) return false;
  }
  return true;
}

bool CameraRenderer::speckle_centre(const Pose2& pose, double co, double si, std::uint64_t h,
                                    std::int64_t i, std::int64_t j, Vec2& world,
                                    Vec2& robot) const {
  world = {(double(i) + 0.2 + 0.6 * unit(h, 16)) * kSpeckleCell,
           (double(j) + 0.2 + 0.6 * unit(h, 32)) * kSpeckleCell};
  const double dx = world.x - pose.x, dy = world.y - pose.y;
  robot = {co * dx + si * dy, -si * dx + co * dy};
  // Outside the robot-frame box of visible floor (the world box is larger when turned)?
  return robot.x >= texture_x0_ - 0.1 && robot.x <= texture_x1_ + 0.1 &&
         std::fabs(robot.y) <= texture_y_ + 0.1;
}

void CameraRenderer::speckle_quad(std::uint64_t h, double cx, double cy) {
  const double half = 0.5 * (0.04 + 0.06 * unit(h, 0));  // 4 to 10 cm across
  const double a = 3.0 * unit(h, 8);
  const double ca = std::cos(a) * half, sa = std::sin(a) * half;
  speckle_.assign({{cx + ca - sa, cy + sa + ca},
                   {cx - ca - sa, cy - sa + ca},
                   {cx - ca + sa, cy - sa - ca},
                   {cx + ca + sa, cy + sa - ca}});
}

void CameraRenderer::draw_texture(const Pose2& pose, cv::Mat& img) {
  const double co = std::cos(pose.yaw_rad), si = std::sin(pose.yaw_rad);
  const CellBox box = texture_cells(pose, texture_x0_, texture_x1_, texture_y_);
  // The region of centres that may show, in the world.
  region_world_.clear();
  for (const Vec2& p : texture_region_) {
    region_world_.push_back({pose.x + co * p.x - si * p.y, pose.y + si * p.x + co * p.y});
  }
  const std::size_t nr = region_world_.size();
  if (nr < 3) return;
  for (std::int64_t i = box.i0; i <= box.i1; ++i) {
    // The region's y range over this column of cells: its vertices in it and its edges' crossings.
    const double xa = double(i) * kSpeckleCell - kSlack, xb = double(i + 1) * kSpeckleCell + kSlack;
    double lo = 1e18, hi = -1e18;
    for (std::size_t k = 0; k < nr; ++k) {
      const Vec2 p = region_world_[k], q = region_world_[(k + 1) % nr];
      if (p.x >= xa && p.x <= xb) {
        lo = std::min(lo, p.y);
        hi = std::max(hi, p.y);
      }
      for (const double x : {xa, xb}) {
        if ((p.x < x) != (q.x < x)) {
          const double y = p.y + (q.y - p.y) * (x - p.x) / (q.x - p.x);
          lo = std::min(lo, y);
          hi = std::max(hi, y);
        }
      }
    }
    if (lo > hi) continue;
    const std::int64_t j0 =
        std::max(box.j0, std::int64_t(std::floor((lo - kSlack) / kSpeckleCell)));
    const std::int64_t j1 =
        std::min(box.j1, std::int64_t(std::floor((hi + kSlack) / kSpeckleCell)));
    for (std::int64_t j = j0; j <= j1; ++j) {
      const std::uint64_t h = cell_hash(i, j);
      Vec2 c, r;
      if (!speckle_centre(pose, co, si, h, i, j, c, r)) continue;
      const double half = 0.5 * (0.04 + 0.06 * unit(h, 0));
      if (!may_show(r.x, r.y, half * kSpeckleRadius)) continue;
      speckle_quad(h, c.x, c.y);
      const double f = speckle_shade(scenario_.floor_speckle, unit(h, 48));
      draw(speckle_, floor_shade(scenario_.floor, f), pose, co, si, img);
    }
  }
}

void CameraRenderer::draw_texture_reference(const Pose2& pose, cv::Mat& img) {
  const double co = std::cos(pose.yaw_rad), si = std::sin(pose.yaw_rad);
  // World box round the robot-frame box of visible floor.
  const CellBox box = texture_cells(pose, texture_x0_, texture_x1_, texture_y_);
  for (std::int64_t i = box.i0; i <= box.i1; ++i) {
    for (std::int64_t j = box.j0; j <= box.j1; ++j) {
      const std::uint64_t h = cell_hash(i, j);
      Vec2 c, r;
      if (!speckle_centre(pose, co, si, h, i, j, c, r)) continue;
      // Shade away from the floor's own: 0.85..0.95 or 1.05..1.15 at the default speckle.
      const double f = speckle_shade(scenario_.floor_speckle, unit(h, 48));
      speckle_quad(h, c.x, c.y);
      draw(speckle_, floor_shade(scenario_.floor, f), pose, co, si, img);
    }
  }
}

void CameraRenderer::draw(const std::vector<Vec2>& pts, Rgb color, const Pose2& pose, double co,
                          double si, cv::Mat& img) {
  const CameraSpec& cs = scenario_.robot.camera;
  // World floor points -> camera frame.
  in_.clear();
  for (const Vec2& w : pts) {
    const double dx = w.x - pose.x, dy = w.y - pose.y;
    in_.push_back(cam_.to_camera(fw::Vec3(co * dx + si * dy, -si * dx + co * dy, 0.0)));
  }
  // Sutherland-Hodgman against the plane z = kNearZ: keeps what is in front of the camera.
  out_.clear();
  for (std::size_t i = 0; i < in_.size(); ++i) {
    const fw::Vec3& a = in_[i];
    const fw::Vec3& b = in_[(i + 1) % in_.size()];
    const bool ain = a.z() >= kNearZ, bin = b.z() >= kNearZ;
    if (ain) out_.push_back(a);
    if (ain != bin) out_.push_back(a + (b - a) * ((kNearZ - a.z()) / (b.z() - a.z())));
  }
  if (out_.size() < 3) return;
  px_.clear();
  double umin = 1e18, umax = -1e18, vmin = 1e18, vmax = -1e18;
  for (const fw::Vec3& p : out_) {
    const double u = cam_.fx() * p.x() / p.z() + cam_.cx();
    const double v = cam_.fx() * p.y() / p.z() + cam_.cy();
    umin = std::min(umin, u);
    umax = std::max(umax, u);
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
    // Clamp far outside values so fixed-point coordinates cannot overflow.
    px_.push_back({int(std::lround(std::clamp(u, -1e5, 1e5) * (1 << kFillShift))),
                   int(std::lround(std::clamp(v, -1e5, 1e5) * (1 << kFillShift)))});
  }
  const bool any_inside = umax >= -1 && umin <= cs.width && vmax >= -1 && vmin <= cs.height;
  if (!any_inside) return;
  const Rgb c = effects_.expose(color);
  if (reference_) {
    // The tests' reference: OpenCV itself, which the project's fill must equal byte for byte.
    cv_px_.clear();
    for (const FixedPt& p : px_) cv_px_.emplace_back(p.x, p.y);
    cv::fillConvexPoly(img, cv_px_.data(), int(cv_px_.size()), cv::Scalar(c.b, c.g, c.r),
                       cv::LINE_8, kFillShift);
  } else {
    // The frame's buffer, so continuous; OpenCV's bytes without its per-call overhead.
    fill_convex_poly(img.data, img.cols, img.rows, px_.data(), int(px_.size()), c.b, c.g, c.r);
    if (keep_drawn_) {
      // The box of the vertices rounded as the fill rounds them, one pixel wider, in the image.
      int x0 = px_[0].x, x1 = x0, y0 = px_[0].y, y1 = y0;
      for (const FixedPt& p : px_) {
        x0 = std::min(x0, p.x);
        x1 = std::max(x1, p.x);
        y0 = std::min(y0, p.y);
        y1 = std::max(y1, p.y);
      }
      constexpr int kHalf = 1 << (kFillShift - 1);
      const int bx0 = std::max(((x0 + kHalf) >> kFillShift) - 1, 0);
      const int bx1 = std::min(((x1 + kHalf) >> kFillShift) + 1, img.cols - 1);
      const int by0 = std::max(((y0 + kHalf) >> kFillShift) - 1, 0);
      const int by1 = std::min(((y1 + kHalf) >> kFillShift) + 1, img.rows - 1);
      if (bx0 <= bx1 && by0 <= by1) {
        drawn_.push_back(
            {std::uint32_t(drawn_pts_.size()), std::uint32_t(px_.size()), bx0, by0, bx1, by1});
        drawn_pts_.insert(drawn_pts_.end(), px_.begin(), px_.end());
      }
    }
  }
}

}  // namespace carril::sim
