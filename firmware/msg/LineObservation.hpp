#pragma once
// Message `line`: one processed camera frame (LinePerception -> FollowLineMission): the tape and
// end-mark blobs found (LineDetector) and where they lie on the floor, robot frame.
#include <cstddef>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

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

// One processed frame.
struct LineObservation {
  LineDetection detection;        // tape and end mark, robot frame
  Pose2 pose;                     // odometry pose the frame was processed at
  bool end_visible = false;       // an end mark wholly in view (its position can be trusted)
  Vec2 end_floor = Vec2::Zero();  // its centre on the floor, robot frame [m]
  // An end mark cut by the image's edge: there, but its centre is not known (detection.end_floor
  // is the visible part's centroid, within the mark's radius of the centre).
  bool end_glimpsed = false;
};

}  // namespace carril::fw
