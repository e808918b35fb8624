#pragma once
// What the light does to a rendered camera frame: exposure (every level times a gain, clipped at
// 255) and glare (GlareSpec: a bright Gaussian patch that sweeps across the image and back once
// per period, at a row drawn from the seed). Applied after the scene is drawn and before the
// pixel noise; nothing is done for exposure 1 and no glare, so such runs are unchanged.
#include <array>
#include <cstdint>
#include <vector>

#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

class CameraEffects {
 public:
  CameraEffects(const Scenario& scenario, std::uint64_t seed);
  bool any() const { return exposure_ != 1.0 || intensity_ > 0.0; }
  // Applies to `frame`, the frame'th of the run (its time is frame / the camera's rate).
  void apply(hal::CameraFrame& frame, std::uint64_t frame_index) const;
  // Exposure alone, to one colour: a frame drawn only in colours (the renderer fills polygons
  // without anti-aliasing) and exposed this way equals the frame drawn and then exposed, at no
  // cost per pixel.
  Rgb expose(Rgb c) const { return {lut_[c.r], lut_[c.g], lut_[c.b]}; }
  // Glare alone (apply() is exposure, then this).
  void apply_glare(hal::CameraFrame& frame, std::uint64_t frame_index) const;
  bool glare() const { return intensity_ > 0.0; }
  // Where the glare's centre is in frame `frame_index` (whole pixels) [px].
  int glare_u(std::uint64_t frame_index, int width) const;
  int glare_v() const { return v_; }
  // The pixels glare adds to in frame `frame_index` of a width x height image: columns u0..u1,
  // rows v0..v1 (inclusive); false when it adds to none.
  bool glare_box(std::uint64_t frame_index, int width, int height, int& u0, int& u1, int& v0,
                 int& v1) const;

 private:
  double exposure_ = 1.0;
  std::array<std::uint8_t, 256> lut_{};
  double intensity_ = 0.0, radius_px_ = 60.0, period_s_ = 4.0, rate_hz_ = 30.0;
  int v_ = 0;  // the glare's row [px]
  // The patch's levels round its centre pixel, (2 reach + 1)^2 x 3 channels, computed once: an
  // exp() per pixel per frame would slow the simulator ten times.
  int reach_ = 0;
  std::vector<std::uint8_t> patch_;
  // glare_box() for a centre already worked out [px].
  bool box_round(int uc, int width, int height, int& u0, int& u1, int& v0, int& v1) const;
};

}  // namespace carril::sim
