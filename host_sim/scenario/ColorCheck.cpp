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

double speckle_shade(double speckle, double u) {
  // The default's own expression: the shades (and so the runs) of scenarios without a speckle
  // key stay exactly as they were.
  if (speckle == kDefaultSpeckle)
    return u < 0.5 ? kFloorShadeMin + 0.2 * u : 1.05 + 0.2 * (u - 0.5);
  const double span = 4.0 * speckle / 3.0;
  return u < 0.5 ? 1.0 - speckle + span * u : 1.0 + speckle / 3.0 + span * (u - 0.5);
}

bool floor_shade_in(const fw::ColorThreshold& t, Rgb floor, double speckle, Rgb& shade_out,
                    double& factor_out) {
  // The flat floor and the ends of the speckles' two shade ranges, exactly as the renderer
  // computes them (a window in HSV holds a scaled colour over an interval of the factor).
  const bool dflt = speckle == kDefaultSpeckle;
  const double lo = dflt ? kFloorShadeMin : 1.0 - speckle,
               hi = dflt ? kFloorShadeMax : 1.0 + speckle;
  const double in_lo = dflt ? 0.95 : 1.0 - speckle / 3.0, in_hi = dflt ? 1.05 : 1.0 + speckle / 3.0;
  for (const double k : {lo, in_lo, 1.0, in_hi, hi}) {
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
