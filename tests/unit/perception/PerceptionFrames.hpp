#pragma once
// Camera frames for the tape detector's tests and benchmark, rendered by the simulator's camera
// from small scenarios built in code, and the thesis's OpenCV pipeline that is the oracle.
// No GoogleTest here: the benchmark uses it too.
#include <cfenv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "firmware/perception/LineDetector.hpp"
#include "hal/Types.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"
#include "host_sim/sensors/CameraRenderer.hpp"

namespace carril::test {

constexpr double kDegPerRad = 180.0 / M_PI;

// One test frame: a robot, its tape and marks, where it stands, and which colour to look for.
struct FrameCase {
  const char* name;
  const char* robot;  // campero | pioneer3at
  const char* lines;  // YAML flow items of `lines:`
  const char* marks;  // YAML flow items of `marks:` ("" for none)
  double noise_std;
  double x, y, yaw_deg;  // robot pose in the world
  const char* color;     // tape colour preset to detect
  bool end_mark;         // compare the end-mark (yellow) detection too
  const char* floor = "[100, 100, 100]";
};

// Pose from which a floor point P of a tape running along world +x is seen `ahead_m` in front of
// the robot and `left_m` to its left, with the tape at `angle_deg` to the robot's heading.
inline sim::Pose2 pose_viewing(double px, double py, double angle_deg, double ahead_m,
                               double left_m) {
  const double yaw = -angle_deg / kDegPerRad;
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {px - ahead_m * c + left_m * s, py - ahead_m * s - left_m * c, yaw};
}

inline sim::Scenario make_scenario(const FrameCase& fc) {
  std::string yaml = "name: perception\nduration_s: 1\nfloor: {color: " + std::string(fc.floor) +
                     "}\nrobot: {preset: " + fc.robot;
  char noise[64];
  std::snprintf(noise, sizeof noise, ", camera: {noise_std: %.1f}", fc.noise_std);
  yaml += std::string(noise) +
          "}\nmission: {type: follow_line, strategy: marks, line_color: " + fc.color +
          "}\nlines: [" + fc.lines + "]\n";
  if (fc.marks[0] != '\0') yaml += std::string("marks: [") + fc.marks + "]\n";
  sim::LoadResult r = sim::load_scenario_text(yaml, fc.name, sim::default_robots_dir());
  if (!r.ok) {
    std::fprintf(stderr, "frame %s: %s\n", fc.name, r.error.c_str());
    std::abort();
  }
  return r.scenario;
}

// A rendered frame with the camera that took it.
struct RenderedFrame {
  FrameCase fc;
  sim::Scenario scenario;
  std::unique_ptr<sim::CameraRenderer> renderer;
  std::unique_ptr<hal::CameraFrame> frame;
  const fw::CameraModel& camera() const { return renderer->model(); }
};

inline std::unique_ptr<RenderedFrame> render_case(const FrameCase& fc, std::uint64_t seed = 1) {
  auto r = std::make_unique<RenderedFrame>();
  r->fc = fc;
  r->scenario = make_scenario(fc);
  r->renderer = std::make_unique<sim::CameraRenderer>(r->scenario, seed);
  r->frame = std::make_unique<hal::CameraFrame>();
  r->renderer->render({fc.x, fc.y, fc.yaw_deg / kDegPerRad}, *r->frame);
  r->frame->seq = 1;
  return r;
}

inline fw::LineDetectorConfig config_for(const char* color, int decimation = 2) {
  fw::LineDetectorConfig cfg;
  if (!fw::color_preset(color, cfg.line) || !fw::color_preset("yellow", cfg.end)) std::abort();
  cfg.decimation = decimation;
  return cfg;
}

// ---- The oracle: the thesis's pipeline, exactly ----

struct OracleResult {
  bool detected = false;
  double area = 0.0;          // cv::contourArea of the largest contour
  double cu = 0.0, cv = 0.0;  // its centroid from cv::moments [px]
  double angle_deg = 0.0;     // cv::fitLine direction, pointing up the image [deg]
  int contours_above = 0;     // contours at least min_area large
};

struct OracleBuffers {
  cv::Mat blur, hsv, mask, mask2;
  std::vector<std::vector<cv::Point>> contours;
};

inline OracleResult opencv_detect(const hal::CameraFrame& f, const fw::ColorThreshold& t,
                                  double min_area, OracleBuffers& b) {
  const cv::Mat img(f.height, f.width, CV_8UC3, const_cast<std::uint8_t*>(f.bgr.data()));
  cv::GaussianBlur(img, b.blur, {5, 5}, 0);
  cv::cvtColor(b.blur, b.hsv, cv::COLOR_BGR2HSV);
  if (t.h_lo <= t.h_hi) {
    cv::inRange(b.hsv, cv::Scalar(t.h_lo, t.s_lo, t.v_lo), cv::Scalar(t.h_hi, t.s_hi, t.v_hi),
                b.mask);
  } else {  // hue window wrapping round 180: two ranges OR'ed
    cv::inRange(b.hsv, cv::Scalar(t.h_lo, t.s_lo, t.v_lo), cv::Scalar(179, t.s_hi, t.v_hi), b.mask);
    cv::inRange(b.hsv, cv::Scalar(0, t.s_lo, t.v_lo), cv::Scalar(t.h_hi, t.s_hi, t.v_hi), b.mask2);
    cv::bitwise_or(b.mask, b.mask2, b.mask);
  }
  cv::erode(b.mask, b.mask, cv::Mat(), {-1, -1}, 2);
  cv::dilate(b.mask, b.mask, cv::Mat(), {-1, -1}, 2);
  cv::findContours(b.mask, b.contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  OracleResult r;
  int best = -1;
  for (int i = 0; i < int(b.contours.size()); ++i) {
    const double a = cv::contourArea(b.contours[std::size_t(i)]);
    if (a >= min_area) ++r.contours_above;
    if (a > r.area) {
      r.area = a;
      best = i;
    }
  }
  if (best < 0 || r.area < min_area) return r;
  const std::vector<cv::Point>& c = b.contours[std::size_t(best)];
  const cv::Moments m = cv::moments(c);
  cv::Vec4f line;
  cv::fitLine(c, line, cv::DIST_L2, 0, 0.01, 0.01);
  double vx = line[0], vy = line[1];
  if (vy > 0 || (vy == 0 && vx < 0)) {
    vx = -vx;
    vy = -vy;
  }
  r.detected = true;
  r.cu = m.m10 / m.m00;
  r.cv = m.m01 / m.m00;
  r.angle_deg = std::atan2(vy, vx) * kDegPerRad;
  return r;
}

// Runs `fn` with the floating-point traps the test main enables switched off: OpenCV's SIMD
// code may compute on padding lanes; the traps are for carril's code.
template <typename Fn>
auto without_fp_traps(Fn fn) {
  const int traps = fegetexcept();
  fedisableexcept(FE_ALL_EXCEPT);
  auto r = fn();
  feclearexcept(FE_ALL_EXCEPT);
  feenableexcept(traps);
  return r;
}

// Difference of two line angles modulo 180 deg, in [-90, 90).
inline double angle_diff_deg(double a, double b) {
  double d = std::fmod(a - b, 180.0);
  if (d >= 90.0) d -= 180.0;
  if (d < -90.0) d += 180.0;
  return d;
}

// ---- The frames ----

constexpr const char* kStraight = "{color: white, points: [[-5, 0], [10, 0]]}";
constexpr const char* kArcLeft =
    "{color: white, arc: {center: [0, 1.5], radius_m: 1.5, start_deg: -120, end_deg: 30}}";
constexpr const char* kArcRight =
    "{color: white, arc: {center: [0, -1.5], radius_m: 1.5, start_deg: 120, end_deg: -30}}";
constexpr const char* kFarTape = "{color: white, points: [[-20, -20], [-19, -20]]}";

// Eight frames of typical tape following, for the benchmark.
inline std::vector<FrameCase> bench_cases() {
  const sim::Pose2 a20 = pose_viewing(0, 0, 20, 1.15, 0), am25 = pose_viewing(0, 0, -25, 1.15, 0);
  return {
      {"straight", "campero", kStraight, "", 0, 0, 0, 0, "white", false},
      {"angle_+20", "campero", kStraight, "", 0, a20.x, a20.y, a20.yaw_rad * kDegPerRad, "white",
       false},
      {"curve_left", "campero", kArcLeft, "", 0, -0.2, 0, 0, "white", false},
      {"corner_left", "campero", "{color: white, points: [[-2, 0], [1.5, 0], [1.5, 3]]}", "", 0, 0,
       0, 0, "white", false},
      {"noise_angle_-25", "campero", kStraight, "", 8, am25.x, am25.y, am25.yaw_rad * kDegPerRad,
       "white", false},
      {"two_colours_red", "campero",
       "{color: white, points: [[-5, 0.15], [10, 0.15]]}, {color: red, points: [[-5, -0.2], [10, "
       "-0.2]]}",
       "", 0, 0, 0, 0, "red", false},
      {"end_mark", "campero", "{color: white, points: [[-5, 0], [1.3, 0]]}",
       "{color: yellow, x: 1.45, y: 0, radius_m: 0.15}", 0, 0, 0, 0, "white", true},
      {"p3at_curve_right", "pioneer3at", kArcRight, "", 4, -0.1, 0, 0, "white", false},
  };
}

}  // namespace carril::test
