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
#include "firmware/msg/LineObservation.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

// HSV window in OpenCV's 8-bit convention: H 0..179 (degrees / 2), S and V 0..255.
// h_lo > h_hi wraps round 180 (red).
struct ColorThreshold {
  std::uint8_t h_lo = 0, h_hi = 179;
  std::uint8_t s_lo = 0, s_hi = 255;
  std::uint8_t v_lo = 0, v_hi = 255;
  bool operator==(const ColorThreshold&) const = default;
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

  // The settings: unit, range, meaning (firmware/core/Param.hpp).
  static std::span<const Param<LineDetectorConfig>> params();
  Status validate() const;
  bool operator==(const LineDetectorConfig&) const = default;
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
