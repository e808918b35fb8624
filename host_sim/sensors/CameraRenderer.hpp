#pragma once
// Renders what the robot's downward-tilted camera sees of the floor: floor colour, tape, marks
// and obstacle footprints, by projecting their ground polygons through the camera model (no
// per-pixel warp), with optional Gaussian pixel noise. Output is the real driver's frame type.
#include <cstdint>
#include <random>
#include <vector>

#include "firmware/perception/CameraModel.hpp"
#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

class CameraRenderer {
 public:
  CameraRenderer(const Scenario& scenario, std::uint64_t seed);
  const fw::CameraModel& model() const { return cam_; }
  // Renders the view from a robot at `pose` into `frame` (width/height set from the camera spec).
  void render(const Pose2& pose, hal::CameraFrame& frame);

 private:
  struct Poly {
    std::vector<Vec2> pts;  // world frame, convex
    Rgb color;
    double cx, cy, r;  // bounding circle, for culling
  };
  void add_poly(std::vector<Vec2> pts, Rgb color);

  const Scenario& scenario_;
  fw::CameraModel cam_;
  std::vector<Poly> polys_;  // drawn in order: obstacles last, over the tape
  double view_radius_m_;     // floor points further than this from the camera are not visible
  double noise_std_;
  std::vector<std::int16_t> noise_;  // precomputed N(0, std) samples
  std::mt19937_64 rng_;
};

fw::CameraMount camera_mount(const CameraSpec& spec);

}  // namespace carril::sim
