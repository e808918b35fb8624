#include "firmware/perception/TapeScanner.hpp"

#include <cstdlib>

namespace carril::fw {

namespace {
inline bool near_color(const std::uint8_t* bgr, Rgb8 c, int tol) {
  return std::abs(int(bgr[2]) - c.r) <= tol && std::abs(int(bgr[1]) - c.g) <= tol &&
         std::abs(int(bgr[0]) - c.b) <= tol;
}
}  // namespace

TapeScanner::TapeScanner(const CameraModel& cam, const FirmwareConfig::Mission& mission)
    : cam_(cam), mission_(mission) {
  const int h = cam.mount().height;
  const int w = cam.mount().width;
  // Bands from the bottom row (nearest floor) up to 10% below the top edge.
  const int top = h / 10;
  for (std::size_t i = 0; i < TapeObservation::kBands; ++i) {
    rows_[i] = (h - 1) - int(i) * (h - 1 - top) / int(TapeObservation::kBands - 1);
  }
  step_ = w >= 320 ? 2 : 1;
  min_band_samples_ = 2;
  min_end_samples_ = 12;
}

bool TapeScanner::scan(const hal::CameraFrame& frame, TapeObservation& out) const {
  if (frame.width != cam_.mount().width || frame.height != cam_.mount().height) return false;
  out = TapeObservation{};
  out.stamp_ns = frame.stamp_ns;
  const int tol = mission_.color_tolerance;
  double end_u = 0.0, end_v = 0.0;
  for (int v : rows_) {
    int count = 0;
    long sum_u = 0;
    for (int u = 0; u < frame.width; u += step_) {
      const std::uint8_t* p = frame.pixel(u, v);
      if (near_color(p, mission_.line_color, tol)) {
        ++count;
        sum_u += u;
      } else if (near_color(p, mission_.end_color, tol)) {
        ++out.end_samples;
        end_u += u;
        end_v += v;
      }
    }
    out.line_samples += count;
    if (count >= min_band_samples_) {
      Vec2 floor;
      if (cam_.pixel_to_floor(Vec2(double(sum_u) / count, v), floor))
        out.line_points.push_back(floor);
    }
  }
  out.line_seen = out.line_points.size() >= 2;
  if (out.end_samples >= min_end_samples_) {
    Vec2 floor;
    if (cam_.pixel_to_floor(Vec2(end_u / out.end_samples, end_v / out.end_samples), floor)) {
      out.end_seen = true;
      out.end_point = floor;
    }
  }
  return true;
}

}  // namespace carril::fw
