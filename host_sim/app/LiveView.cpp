#include "host_sim/app/LiveView.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>

#include "host_sim/app/ViewWindow.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

namespace {
const char* kWindow = "carril_sim";
cv::Scalar bgr(Rgb c) {
  return cv::Scalar(c.b, c.g, c.r);
}

// libcarril_sim_window.so, beside the carril_sim executable (ViewWindow.hpp says why it is not
// linked in).
struct WindowModule {
  void* handle = nullptr;
  decltype(&carril_view_open) open = nullptr;
  decltype(&carril_view_show) show = nullptr;
  decltype(&carril_view_close) close = nullptr;

  bool load(std::string& why) {
    char exe[4096];
    const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) {
      why = "cannot find carril_sim's own path (/proc/self/exe)";
      return false;
    }
    std::string path(exe, std::size_t(n));
    path = path.substr(0, path.rfind('/') + 1) + "libcarril_sim_window.so";
    handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* e = ::dlerror();
      why = "cannot load the window module " + path + ": " + (e ? e : "unknown error") +
            " (build the carril_sim_window target)";
      return false;
    }
    open = reinterpret_cast<decltype(open)>(::dlsym(handle, "carril_view_open"));
    show = reinterpret_cast<decltype(show)>(::dlsym(handle, "carril_view_show"));
    close = reinterpret_cast<decltype(close)>(::dlsym(handle, "carril_view_close"));
    if (open == nullptr || show == nullptr || close == nullptr) {
      why = path + " lacks the carril_view_* functions (a stale build?)";
      return false;
    }
    return true;
  }
};
}  // namespace

struct LiveView::Impl {
  WindowModule window;
  const Scenario& scenario;
  cv::Mat background;
  double scale = 50.0, min_x = 0.0, max_y = 0.0;
  double since_draw_s = 1.0;
  std::vector<cv::Point> path;

  explicit Impl(const Scenario& s) : scenario(s) {
    double x0 = s.robot.start.x, x1 = x0, y0 = s.robot.start.y, y1 = y0;
    auto grow = [&](double x, double y) {
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    };
    for (const auto& l : s.lines)
      for (const auto& p : l.points) grow(p.x, p.y);
    for (const auto& o : s.obstacles) grow(o.center.x, o.center.y);
    for (const auto& w : s.walls)
      for (const auto& p : w.points) grow(p.x, p.y);
    x0 -= 1.5, x1 += 1.5, y0 -= 1.5, y1 += 1.5;
    scale = std::min(800.0 / (x1 - x0), 800.0 / (y1 - y0));
    min_x = x0;
    max_y = y1;
    background = cv::Mat(int((y1 - y0) * scale), int((x1 - x0) * scale), CV_8UC3, bgr(s.floor));
    for (const auto& l : s.lines) {
      std::vector<cv::Point> pts;
      for (const auto& p : l.points) pts.push_back(px(p.x, p.y));
      cv::polylines(background, pts, false, bgr(l.color), std::max(1, int(l.width_m * scale)));
    }
    for (const auto& m : s.marks)
      cv::circle(background, px(m.center.x, m.center.y), int(m.radius_m * scale), bgr(m.color), -1);
    for (const auto& o : s.obstacles) {
      if (o.shape == ObstacleShape::Cylinder) {
        cv::circle(background, px(o.center.x, o.center.y), int(o.radius_m * scale),
                   cv::Scalar(50, 50, 50), -1);
      } else {
        const cv::RotatedRect r(px(o.center.x, o.center.y),
                                cv::Size2f(float(o.size_x_m * scale), float(o.size_y_m * scale)),
                                float(-o.yaw_rad * 180.0 / fw::kPi));
        cv::Point2f c[4];
        r.points(c);
        std::vector<cv::Point> v(c, c + 4);
        cv::fillConvexPoly(background, v, cv::Scalar(50, 50, 50));
      }
    }
    for (const auto& w : s.walls) {
      for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
        cv::line(background, px(w.points[i].x, w.points[i].y),
                 px(w.points[i + 1].x, w.points[i + 1].y), cv::Scalar(30, 30, 30),
                 std::max(1, int(w.thickness_m * scale)));
      }
    }
  }
  cv::Point px(double x, double y) const {
    return {int((x - min_x) * scale), int((max_y - y) * scale)};
  }
};

std::unique_ptr<LiveView> LiveView::open(const Scenario& scenario, std::string& why) {
  const char* display = std::getenv("DISPLAY");
  if (display == nullptr || *display == '\0') {
    why = "no display (DISPLAY is not set); run without --view, or under a desktop or Xvfb";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>(scenario);
  if (!impl->window.load(why)) return nullptr;
  if (impl->window.open(kWindow) != 0) {
    why = "cannot open a window on display " + std::string(display);
    return nullptr;
  }
  return std::unique_ptr<LiveView>(new LiveView(std::move(impl)));
}

LiveView::LiveView(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LiveView::~LiveView() {
  impl_->window.close();
}

bool LiveView::update(SimRun& run, double dt_s) {
  Impl& v = *impl_;
  const auto& rows = run.rows();
  if (!rows.empty()) v.path.push_back(v.px(rows.back().x, rows.back().y));
  v.since_draw_s += dt_s;
  if (v.since_draw_s < 1.0 / 30.0) return true;
  v.since_draw_s = 0.0;

  cv::Mat top = v.background.clone();
  if (v.path.size() > 1) cv::polylines(top, v.path, false, cv::Scalar(255, 120, 0), 2);
  const Pose2 p = run.topology().world.pose();
  const RobotSpec& r = run.scenario().robot;
  const cv::RotatedRect body(v.px(p.x, p.y),
                             cv::Size2f(float(r.length_m * v.scale), float(r.width_m * v.scale)),
                             float(-p.yaw_rad * 180.0 / fw::kPi));
  cv::Point2f c[4];
  body.points(c);
  for (int i = 0; i < 4; ++i) cv::line(top, c[i], c[(i + 1) % 4], cv::Scalar(0, 0, 255), 2);
  cv::putText(
      top,
      cv::format("t %.1f s  %s  progress %.2f", run.sim_time_s(), run.state_name(), run.progress()),
      {10, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 2);

  const hal::CameraFrame& f = run.topology().camera.back_buffer();
  cv::Mat cam(f.height, f.width, CV_8UC3, const_cast<std::uint8_t*>(f.bgr.data()));
  cv::Mat cam_small;
  const double k = double(top.rows) / std::max(1, cam.rows) * 0.6;
  cv::resize(cam, cam_small, cv::Size(), k, k);
  cv::Mat canvas(std::max(top.rows, cam_small.rows + 40), top.cols + cam_small.cols, CV_8UC3,
                 cv::Scalar(40, 40, 40));
  top.copyTo(canvas(cv::Rect(0, 0, top.cols, top.rows)));
  cam_small.copyTo(canvas(cv::Rect(top.cols, 0, cam_small.cols, cam_small.rows)));
  cv::putText(canvas, cv::format("camera %dx%d (robot's view, up = ahead)", f.width, f.height),
              {top.cols + 10, cam_small.rows + 28}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(230, 230, 230), 1);
  return v.window.show(kWindow, canvas.rows, canvas.cols, canvas.data, canvas.step[0]) == 1;
}

}  // namespace carril::sim
