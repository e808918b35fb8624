// carril's LineDetector against the thesis's OpenCV pipeline (GaussianBlur 5x5, HSV, inRange,
// erode x2, dilate x2, findContours, largest contour's moments and fitLine) on frames rendered by
// the simulator's camera. Same verdict on every frame; where the oracle finds tape, centroid
// within 1 px and direction within 1 deg. Prints the table of both results.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "firmware/perception/ColorClassifier.hpp"
#include "firmware/perception/LineDetector.hpp"
#include "tests/unit/perception/PerceptionFrames.hpp"

namespace carril::test {
namespace {

constexpr double kCentroidTolPx = 1.0;
constexpr double kAngleTolDeg = 1.0;

FrameCase at(const char* name, const char* robot, const char* lines, sim::Pose2 p,
             const char* color = "white", double noise = 0, const char* marks = "",
             bool end = false, const char* floor = "[100, 100, 100]") {
  return {name, robot, lines, marks, noise, p.x, p.y, p.yaw_rad * kDegPerRad, color, end, floor};
}

std::vector<FrameCase> oracle_cases() {
  const char* C = "campero";
  const char* P = "pioneer3at";
  const char* two =
      "{color: white, points: [[-5, 0.15], [10, 0.15]]}, "
      "{color: red, points: [[-5, -0.2], [10, -0.2]]}";
  const char* cross =
      "{color: white, points: [[-5, 0.05], [10, 0.05]]}, "
      "{color: red, points: [[0.6, -0.8], [2.0, 0.9]]}";
  const char* corner_l = "{color: white, points: [[-2, 0], [1.5, 0], [1.5, 3]]}";
  const char* corner_r = "{color: white, points: [[-2, 0], [1.6, 0], [1.6, -3]]}";
  const char* end_tape = "{color: white, points: [[-5, 0], [1.3, 0]]}";
  auto pv = pose_viewing;
  std::vector<FrameCase> v = {
      at("straight", C, kStraight, {0, 0, 0}),
      at("straight_left_0.15", C, kStraight, pv(0, 0, 0, 1.15, 0.15)),
      at("straight_right_0.30", C, kStraight, pv(0, 0, 0, 1.15, -0.30)),
      at("angle_+20", C, kStraight, pv(0, 0, 20, 1.15, 0)),
      at("angle_-20", C, kStraight, pv(0, 0, -20, 1.15, 0)),
      at("angle_+40", C, kStraight, pv(0, 0, 40, 1.15, 0)),
      at("angle_-40", C, kStraight, pv(0, 0, -40, 1.15, 0)),
      at("angle_+30_left_0.2", C, kStraight, pv(0, 0, 30, 1.15, 0.2)),
      at("angle_-10_right_0.2", C, kStraight, pv(0, 0, -10, 1.0, -0.2)),
      at("curve_left_r1.5", C, kArcLeft, {-0.2, 0, 0}),
      at("curve_right_r1.5", C, kArcRight, {-0.2, 0, 0}),
      at("curve_left_yaw_+15", C, kArcLeft, {-0.1, 0, 0.26}),
      at("corner_left", C, corner_l, {0, 0, 0}),
      at("corner_right", C, corner_r, {0, 0, 0}),
      at("two_colours_white", C, two, {0, 0, 0}, "white"),
      at("two_colours_red", C, two, {0, 0, 0}, "red"),
      at("crossing_white", C, cross, {0, 0, 0}, "white"),
      at("crossing_red", C, cross, {0, 0, 0}, "red"),
      at("noise_straight", C, kStraight, {0, 0, 0}, "white", 8),
      at("noise_angle_+25", C, kStraight, pv(0, 0, 25, 1.15, 0), "white", 8),
      at("noise_curve_right", C, kArcRight, {-0.2, 0, 0}, "white", 8),
      at("edge_right", C, kStraight, pv(0, 0, 0, 1.15, -0.52)),
      at("edge_left_angled_60", C, kStraight, pv(0, 0, 60, 1.0, 0.45)),
      at("edge_angled_45_right", C, kStraight, pv(0, 0, 45, 0.5, -0.75)),
      at("edge_right_0.55_near_min", C, kStraight, pv(0, 0, 0, 1.15, -0.55)),
      at("edge_sliver_below_min", C, kStraight, pv(0, 0, 0, 1.15, -0.65)),
      at("no_tape", C, kFarTape, {0, 0, 0}),
      at("no_tape_noise", C, kFarTape, {0, 0, 0}, "white", 8),
      at("red_angle_+15", C, "{color: red, points: [[-5, 0], [10, 0]]}", pv(0, 0, 15, 1.15, 0),
         "red"),
      at("blue_angle_-30", C, "{color: blue, points: [[-5, 0], [10, 0]]}", pv(0, 0, -30, 1.15, 0.1),
         "blue"),
      at("green_straight", C, "{color: green, points: [[-5, 0], [10, 0]]}", {0, 0.1, 0}, "green"),
      at("black_on_light_floor", C, "{color: black, points: [[-5, 0], [10, 0]]}",
         pv(0, 0, 10, 1.15, 0), "black", 0, "", false, "[190, 190, 190]"),
      at("end_mark_ahead", C, end_tape, {0, 0, 0}, "white", 0,
         "{color: yellow, x: 1.45, y: 0, radius_m: 0.15}", true),
      at("end_mark_offset_small", C, kStraight, {0, 0, 0}, "white", 0,
         "{color: yellow, x: 1.0, y: 0.25, radius_m: 0.08}", true),
      at("end_mark_noise", C, end_tape, {0.1, 0, 0.1}, "white", 8,
         "{color: yellow, x: 1.45, y: 0, radius_m: 0.15}", true),
      at("p3at_straight", P, kStraight, {0, 0, 0}),
      at("p3at_angle_+30", P, kStraight, pv(0, 0, 30, 0.75, 0)),
      at("p3at_curve_left", P, kArcLeft, {-0.1, 0, 0}),
      at("p3at_corner_left", P, "{color: white, points: [[-2, 0], [0.95, 0], [0.95, 3]]}",
         {0, 0, 0}),
      at("p3at_end_mark", P, "{color: white, points: [[-5, 0], [0.9, 0]]}", {0, 0, 0}, "white", 0,
         "{color: yellow, x: 1.0, y: 0, radius_m: 0.1}", true),
  };
  return v;
}

struct Row {
  const char* name;
  const char* what;
  OracleResult o;
  bool c_det;
  double cu, cv, ang, area;
  double e_px, e_deg;
};

void print_row(const Row& r) {
  char oc[64] = "-", cc[64] = "-", err[48] = "";
  if (r.o.detected) {
    std::snprintf(oc, sizeof oc, "%7.2f %7.2f %8.2f %7.0f", r.o.cu, r.o.cv, r.o.angle_deg,
                  r.o.area);
  } else if (r.o.area > 0) {
    std::snprintf(oc, sizeof oc, "- (largest contour %.0f)", r.o.area);
  }
  if (r.c_det) std::snprintf(cc, sizeof cc, "%7.2f %7.2f %8.2f %7.0f", r.cu, r.cv, r.ang, r.area);
  if (r.o.detected && r.c_det) std::snprintf(err, sizeof err, "%6.3f %6.3f", r.e_px, r.e_deg);
  std::printf("%-24s %-4s | %-33s | %-33s | %s\n", r.name, r.what, oc, cc, err);
}

// Runs carril at `decimation` and the oracle on every frame; checks verdicts and tolerances.
void compare_with_oracle(int decimation, bool print_table) {
  const std::vector<FrameCase> cases = oracle_cases();
  ASSERT_GE(cases.size(), 30U);
  OracleBuffers ob;
  double worst_px = 0, worst_deg = 0;
  int compared = 0;
  if (print_table) {
    std::printf("%-24s %-4s | %-33s | %-33s | %s\n", "frame", "mask",
                "oracle u       v     angle    area", "carril u       v     angle    area",
                "err px  deg");
  }
  for (const FrameCase& fc : cases) {
    const auto rf = render_case(fc);
    fw::LineDetectorConfig cfg = config_for(fc.color, decimation);
    // The oracle is the thesis's pipeline, whose minimum is a pixel count: compare like with like.
    cfg.min_area_px =
        6000.0 * rf->camera().mount().width * rf->camera().mount().height / (640.0 * 480.0);
    fw::LineDetector det(rf->camera(), cfg);
    fw::LineDetection d;
    ASSERT_TRUE(det.detect(*rf->frame, d)) << fc.name;
    for (int pass = 0; pass < (fc.end_mark ? 2 : 1); ++pass) {
      const bool end = pass == 1;
      const fw::ColorThreshold& t = end ? det.config().end : det.config().line;
      const double min_area = end ? det.config().min_end_area_px : det.config().min_area_px;
      const OracleResult o =
          without_fp_traps([&] { return opencv_detect(*rf->frame, t, min_area, ob); });
      Row r{fc.name, end ? "end" : "line", o, end ? d.end_detected : d.detected, 0, 0, 0, 0, 0, 0};
      if (r.c_det) {
        const fw::Blob& b = end ? d.end_blob : d.blobs[0];
        r.cu = b.centroid_px.x();
        r.cv = b.centroid_px.y();
        r.ang = b.angle_deg;
        r.area = b.area_px;
      }
      if (o.detected && r.c_det) {
        r.e_px = std::hypot(r.cu - o.cu, r.cv - o.cv);
        r.e_deg = std::fabs(angle_diff_deg(r.ang, o.angle_deg));
      }
      if (print_table) print_row(r);
      EXPECT_EQ(o.detected, r.c_det) << fc.name << " " << r.what << " decimation " << decimation
                                     << ": oracle area " << o.area << ", carril area " << r.area;
      if (!o.detected || !r.c_det) continue;
      ++compared;
      worst_px = std::fmax(worst_px, r.e_px);
      EXPECT_LE(r.e_px, kCentroidTolPx) << fc.name << " " << r.what << " decimation " << decimation;
      if (!end) {  // a disc has no direction
        worst_deg = std::fmax(worst_deg, r.e_deg);
        EXPECT_LE(r.e_deg, kAngleTolDeg) << fc.name << " decimation " << decimation;
      }
    }
  }
  std::printf(
      "decimation %d: %zu frames, %d detections compared: worst centroid error %.3f px, "
      "worst angle error %.3f deg\n",
      decimation, cases.size(), compared, worst_px, worst_deg);
}

// The default configuration (decimation 2), with the table.
TEST(LineDetectorOracleTest, MatchesOpenCvPipelineOnRenderedFrames) {
  compare_with_oracle(2, true);
}

// The other decimations hold the same tolerances.
TEST(LineDetectorOracleTest, OtherDecimationsMatchToo) {
  compare_with_oracle(1, false);
  compare_with_oracle(4, false);
}

// The firmware's integer HSV is OpenCV's cvtColor(COLOR_BGR2HSV), value for value.
TEST(LineDetectorOracleTest, HsvMatchesOpenCv) {
  cv::Mat bgr(1, 32 * 32 * 32, CV_8UC3), hsv;
  int i = 0;
  for (int b = 0; b < 256; b += 8) {
    for (int g = 0; g < 256; g += 8) {
      for (int r = 0; r < 256; r += 8) {
        bgr.at<cv::Vec3b>(0, i++) = cv::Vec3b(std::uint8_t(b + 7 * (r & 8) / 8),
                                              std::uint8_t(g + 3 * (b & 8) / 8), std::uint8_t(r));
      }
    }
  }
  without_fp_traps([&] {
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
    return 0;
  });
  int mismatches = 0;
  for (int k = 0; k < bgr.cols; ++k) {
    const cv::Vec3b c = bgr.at<cv::Vec3b>(0, k), h = hsv.at<cv::Vec3b>(0, k);
    const fw::Hsv8 m = fw::bgr_to_hsv8(c[0], c[1], c[2]);
    if (m.h != h[0] || m.s != h[1] || m.v != h[2]) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace carril::test
