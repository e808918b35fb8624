#include "host_sim/sensors/CameraRenderer.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace carril::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr int kShift = 4;        // sub-pixel bits for cv::fillConvexPoly
constexpr double kNearZ = 0.02;  // clip polygons this close to the camera plane [m]

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

fw::CameraMount camera_mount(const CameraSpec& s) {
  fw::CameraMount m;
  m.x_m = s.x_m;
  m.y_m = s.y_m;
  m.z_m = s.z_m;
  m.tilt_rad = s.tilt_deg * kDeg;
  m.hfov_rad = s.hfov_deg * kDeg;
  m.width = s.width;
  m.height = s.height;
  return m;
}

CameraRenderer::CameraRenderer(const Scenario& scenario, std::uint64_t seed)
    : scenario_(scenario),
      cam_(camera_mount(scenario.robot.camera)),
      noise_std_(scenario.robot.camera.noise_std),
      rng_(seed ^ 0xCA3E4A11ULL) {
  for (const LineSpec& l : scenario.lines) {
    const double h = l.width_m / 2;
    for (std::size_t i = 0; i + 1 < l.points.size(); ++i) {
      const Vec2 a = l.points[i], b = l.points[i + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      if (len < 1e-9) continue;
      const double nx = -(b.y - a.y) / len * h, ny = (b.x - a.x) / len * h;
      add_poly(
          {{a.x + nx, a.y + ny}, {b.x + nx, b.y + ny}, {b.x - nx, b.y - ny}, {a.x - nx, a.y - ny}},
          l.color);
      // Round joins, so corners have no notch (only where the direction changes noticeably).
      if (i + 2 < l.points.size()) {
        const Vec2 c = l.points[i + 2];
        const double cross = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
        const double len2 = std::hypot(c.x - b.x, c.y - b.y);
        if (len2 > 1e-9 && std::fabs(cross / (len * len2)) > 0.05)
          add_poly(disk(b, h, 16), l.color);
      }
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
  if (noise_std_ > 0) {
    // A table of noise samples, read from a random offset each frame: per-pixel Gaussian draws
    // would cost more than the rest of the simulation together.
    std::normal_distribution<double> n(0.0, noise_std_);
    noise_.resize(1 << 20);
    for (auto& v : noise_)
      v = static_cast<std::int16_t>(std::lround(std::clamp(n(rng_), -255.0, 255.0)));
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

void CameraRenderer::render(const Pose2& pose, hal::CameraFrame& frame) {
  const CameraSpec& cs = scenario_.robot.camera;
  frame.width = static_cast<std::uint16_t>(cs.width);
  frame.height = static_cast<std::uint16_t>(cs.height);
  cv::Mat img(cs.height, cs.width, CV_8UC3, frame.bgr.data());
  const Rgb f = scenario_.floor;
  img.setTo(cv::Scalar(f.b, f.g, f.r));

  const double co = std::cos(pose.yaw_rad), si = std::sin(pose.yaw_rad);
  const double cam_wx = pose.x + co * cs.x_m - si * cs.y_m;
  const double cam_wy = pose.y + si * cs.x_m + co * cs.y_m;
  std::vector<fw::Vec3> in, out;
  std::vector<cv::Point> px;
  for (const Poly& poly : polys_) {
    if (std::hypot(poly.cx - cam_wx, poly.cy - cam_wy) > view_radius_m_ + poly.r) continue;
    // World floor points -> camera frame.
    in.clear();
    for (const Vec2& w : poly.pts) {
      const double dx = w.x - pose.x, dy = w.y - pose.y;
      in.push_back(cam_.to_camera(fw::Vec3(co * dx + si * dy, -si * dx + co * dy, 0.0)));
    }
    // Sutherland-Hodgman against the plane z = kNearZ: keeps what is in front of the camera.
    out.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
      const fw::Vec3& a = in[i];
      const fw::Vec3& b = in[(i + 1) % in.size()];
      const bool ain = a.z() >= kNearZ, bin = b.z() >= kNearZ;
      if (ain) out.push_back(a);
      if (ain != bin) out.push_back(a + (b - a) * ((kNearZ - a.z()) / (b.z() - a.z())));
    }
    if (out.size() < 3) continue;
    px.clear();
    bool any_inside = false;
    double umin = 1e18, umax = -1e18, vmin = 1e18, vmax = -1e18;
    for (const fw::Vec3& p : out) {
      const double u = cam_.fx() * p.x() / p.z() + cam_.cx();
      const double v = cam_.fx() * p.y() / p.z() + cam_.cy();
      umin = std::min(umin, u);
      umax = std::max(umax, u);
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
      // Clamp far outside values so fixed-point coordinates cannot overflow.
      px.emplace_back(int(std::lround(std::clamp(u, -1e5, 1e5) * (1 << kShift))),
                      int(std::lround(std::clamp(v, -1e5, 1e5) * (1 << kShift))));
    }
    any_inside = umax >= -1 && umin <= cs.width && vmax >= -1 && vmin <= cs.height;
    if (!any_inside) continue;
    cv::fillConvexPoly(img, px.data(), int(px.size()),
                       cv::Scalar(poly.color.b, poly.color.g, poly.color.r), cv::LINE_8, kShift);
  }

  if (noise_std_ > 0) {
    const std::size_t n = std::size_t(cs.width) * cs.height * 3;
    std::size_t k = std::uniform_int_distribution<std::size_t>(0, noise_.size() - 1)(rng_);
    std::uint8_t* d = frame.bgr.data();
    for (std::size_t i = 0; i < n; ++i) {
      d[i] = static_cast<std::uint8_t>(std::clamp(int(d[i]) + noise_[k], 0, 255));
      if (++k == noise_.size()) k = 0;
    }
  }
}

}  // namespace carril::sim
