#pragma once
// Minimal tape perception for the walking skeleton: samples a fixed set of image rows, finds the
// tape colour's centroid in each, and maps those centroids to floor points in the robot frame.
// Also locates the end-mark colour. No heap, no OpenCV.
#include <cstdint>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct TapeObservation {
  static constexpr std::size_t kBands = 24;
  hal::TimeNs stamp_ns = 0;
  bool line_seen = false;
  StaticVector<Vec2, kBands> line_points;  // floor points, robot frame, nearest first [m]
  int line_samples = 0;                    // sampled pixels of the line colour
  bool end_seen = false;
  Vec2 end_point = Vec2::Zero();  // centroid of the end-mark colour on the floor, robot frame [m]
  int end_samples = 0;
};

class TapeScanner {
 public:
  TapeScanner(const CameraModel& cam, const FirmwareConfig::Mission& mission);
  // False (and `out` untouched) when the frame does not match the configured camera size.
  bool scan(const hal::CameraFrame& frame, TapeObservation& out) const;

 private:
  const CameraModel& cam_;
  FirmwareConfig::Mission mission_;
  int rows_[TapeObservation::kBands];
  int step_;  // sample every step_ pixels along a row
  int min_band_samples_;
  int min_end_samples_;
};

}  // namespace carril::fw
