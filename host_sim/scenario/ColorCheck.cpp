#include "host_sim/scenario/ColorCheck.hpp"

#include <algorithm>
#include <cmath>

namespace carril::sim {

Rgb floor_shade(Rgb c, double f) {
  const bool dark = c.r < 56 && c.g < 56 && c.b < 56;
  auto ch = [&](std::uint8_t v) {
    const double x = dark ? double(v) + (f - 1.0) * 80.0 : double(v) * f;
    return static_cast<std::uint8_t>(std::clamp(std::lround(x), 0L, 255L));
  };
  return {ch(c.r), ch(c.g), ch(c.b)};
}

bool floor_shade_in(const fw::ColorThreshold& t, Rgb floor, Rgb& shade_out, double& factor_out) {
  // The flat floor and the ends of the speckles' two shade ranges, exactly as the renderer
  // computes them (a window in HSV holds a scaled colour over an interval of the factor).
  for (const double k : {kFloorShadeMin, 0.95, 1.0, 1.05, kFloorShadeMax}) {
    const Rgb rendered = floor_shade(floor, k);
    if (detector_sees(t, rendered)) {
      shade_out = rendered;
      factor_out = k;
      return true;
    }
  }
  return false;
}

}  // namespace carril::sim
