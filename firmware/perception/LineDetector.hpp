#pragma once
// Tape perception inside the tick: colour threshold in HSV (robust to shading), noise cleanup
// equivalent to the thesis's 5x5 blur + 2 erosions + 2 dilations, connected blobs with a minimum
// area, the largest blob's centroid and principal direction, a second mask for the end-mark
// colour, and the result mapped to the floor in the robot frame through the camera homography.
// No heap, no OpenCV: every buffer is sized at construction for the configured camera.
// OpenCV's pipeline is the oracle it is tested against (tests/unit/perception).
#include <cstdint>
#include <memory>

#include "firmware/core/StaticVector.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// HSV window in OpenCV's 8-bit convention: H 0..179 (degrees / 2), S and V 0..255.
// h_lo > h_hi wraps round 180 (red).
struct ColorThreshold {
  std::uint8_t h_lo = 0, h_hi = 179;
  std::uint8_t s_lo = 0, s_hi = 255;
  std::uint8_t v_lo = 0, v_hi = 255;
};

// Presets for the named tape colours: white, black, red, green, blue, yellow.
bool color_preset(const char* name, ColorThreshold& out);
// A window round an arbitrary RGB colour (for [r, g, b] colours in scenario files).
ColorThreshold threshold_around_rgb(std::uint8_t r, std::uint8_t g, std::uint8_t b);

struct LineDetectorConfig {
  ColorThreshold line;  // tape colour
  ColorThreshold end;   // end-mark colour
  int decimation = 2;   // work on every n-th pixel block (n x n averaged): 1, 2 or 4
  // A tape blob counts when it covers at least a piece of tape min_piece_m long on the floor:
  // its pixel area times the floor area of a pixel where it lies (through the camera model) is at
  // least tape_width_m x min_piece_m, so the same piece counts near the robot and far away. A
  // blob of the thesis's 6000 px (scaled) counts wherever it lies: tape on its own (`sure`).
  double tape_width_m = 0.05;  // the tape's width [m]
  double min_piece_m = 0.08;   // the shortest stretch of tape taken for tape [m]
  double min_area_px = 0;      // > 0: a fixed minimum blob area in full-resolution pixels
                               // instead (the thesis's 6000 at 640x480); 0: the floor rule above
  double min_end_area_px = 0;  // minimum end-mark area; 0 = 1500 scaled the same way
  // Classify only the blocks near sampled blocks of either colour (exact: see LineDetector.cpp);
  // false: every block of every frame (the reference the tests compare it with).
  bool sparse = true;

  Status validate() const;
};

// One connected blob of the mask, in full-resolution pixel coordinates.
struct Blob {
  static constexpr std::size_t kCenterline = 16;
  double area_px = 0.0;
  Vec2 centroid_px = Vec2::Zero();  // (u, v)
  // Principal direction of the blob's outline (as cv::fitLine on its contour), unit vector
  // pointing up the image (dv <= 0, i.e. ahead of the robot).
  Vec2 axis_px = Vec2(0.0, -1.0);
  double angle_deg = 0.0;   // atan2 of axis_px in the image, degrees, in (-180, 0]
  double elongation = 0.0;  // sqrt(major / minor eigenvalue) of the area's covariance, >= 1
  int u_min = 0, u_max = 0, v_min = 0, v_max = 0;  // bounding box, inclusive
  bool touches_edge = false;
  // The blob's centre line: the centroid of its pixels in up to 16 bands of rows, bottom first.
  StaticVector<Vec2, kCenterline> centerline_px;
};

struct LineDetection {
  hal::TimeNs stamp_ns = 0;
  std::uint32_t seq = 0;
  bool detected = false;  // a tape blob at least the minimum (see LineDetectorConfig) found
  // The largest blob is at least the size that is tape on its own (the thesis's 6000 px at
  // 640x480, or min_area_px): smaller ones are pieces of worn tape, or specks, and count only
  // where they continue the tape seen before (FollowLineMission, TapeMap::continues).
  bool sure = false;
  float confidence = 0.0F;      // 0..1: area, elongation and agreement of the blobs
  StaticVector<Blob, 4> blobs;  // tape blobs above min area, largest first (forks, second segments)
  // The largest tape blob on the floor, robot frame (x forward, y left) [m, rad]:
  Vec2 centroid_floor = Vec2::Zero();
  double angle_floor_rad = 0.0;    // tape direction relative to the robot's x axis
  Vec2 near_floor = Vec2::Zero();  // nearest centre-line point
  Vec2 far_floor = Vec2::Zero();   // farthest centre-line point
  StaticVector<Vec2, Blob::kCenterline> centerline_floor;  // bottom (near) first
  // End mark (largest blob of the end colour above min_end_area_px):
  bool end_detected = false;
  Blob end_blob;
  Vec2 end_floor = Vec2::Zero();  // its centroid on the floor, robot frame [m]
};

class LineDetector {
 public:
  LineDetector(const CameraModel& camera, const LineDetectorConfig& config);
  ~LineDetector();
  LineDetector(const LineDetector&) = delete;
  LineDetector& operator=(const LineDetector&) = delete;

  // Processes one frame. False (and `out` untouched) when the frame's size differs from the
  // camera the detector was built for.
  //
  // Sparse classification: every third block of every third row (and the last row and column)
  // is classified, then only the blocks within 2 (at d = 1, 4) of a sampled block of either
  // colour. The cleaned-up masks are exactly the whole frame's: every blob the cleanup keeps is
  // a union of squares that each hold a sampled block.
  bool detect(const hal::CameraFrame& frame, LineDetection& out);

  const LineDetectorConfig& config() const { return cfg_; }
  // The floor area one pixel at px covers [m^2]; 0 when its corners do not all map to the floor.
  double pixel_floor_area_m2(const Vec2& px) const;
  // The smallest tape blob that can count anywhere in the image [px] (its pixel minimum, or the
  // floor rule's smallest pixel area where a pixel covers the most floor).
  double min_blob_px() const { return min_blob_px_; }
  // A blob at least this large is tape on its own (LineDetection::sure) [px].
  double sure_area_px() const { return ref_area_px_; }

  // Blocks classified so far, samples included (for tests and profiling).
  std::uint64_t classified_blocks() const { return classified_blocks_; }
  // At d = 2, sparse: times the floor box was grown, and runs of eight samples tested against
  // it so far, and how many of those lay inside it (their verdicts taken as 0 without lookups).
  std::uint64_t floor_boxes() const { return floor_boxes_; }
  std::uint64_t box_runs_tested() const { return box_runs_tested_; }
  std::uint64_t box_runs_inside() const { return box_runs_inside_; }

 private:
  struct Buffers;  // mask, run and label storage, sized at construction
  const CameraModel& cam_;
  LineDetectorConfig cfg_;
  std::unique_ptr<Buffers> buf_;
  double min_floor_m2_ = 0.0;  // the floor rule's area; 0: min_area_px rules
  double min_blob_px_ = 0.0;
  double ref_area_px_ = 0.0;  // tape on its own, and the confidence's size unit: 6000 px scaled,
                              // or min_area_px
  std::uint64_t classified_blocks_ = 0;
  std::uint64_t floor_boxes_ = 0, box_runs_tested_ = 0, box_runs_inside_ = 0;
};

}  // namespace carril::fw
