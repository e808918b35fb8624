#pragma once
// The check the scenario loader makes with the tape detector's colour windows (the shared
// loader's, as the firmware is configured with them): the floor, as rendered, must not look like
// the tape or the end mark, and the tape must not look like the end mark.
#include <string>

#include "firmware/perception/ColorClassifier.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "loader/ColorThreshold.hpp"

namespace carril::sim {

// The detector's window for a mission colour, and whether it holds a colour: the firmware's, as
// the shared loader configures it (loader/ColorThreshold.hpp).
using loader::detector_sees;
using loader::detector_threshold;

// The rendered floor's texture (host_sim/sensors/CameraRenderer) shades the floor colour by a
// factor in [1 - s, 1 - s/3] or [1 + s/3, 1 + s], s the floor's speckle (floor.speckle; by
// default kDefaultSpeckle: [kFloorShadeMin, 0.95] or [1.05, kFloorShadeMax]).
inline constexpr double kDefaultSpeckle = 0.15;
inline constexpr double kFloorShadeMin = 0.85;
inline constexpr double kFloorShadeMax = 1.15;

// A speckle's shade factor for a uniform draw u in [0, 1): below 0.5 the dark range, above it
// the light one.
double speckle_shade(double speckle, double u);

// The floor colour shaded by factor f: each channel times f, rounded, clamped to 255; a floor
// darker than 56 in every channel (where a factor would change little) gets (f - 1) * 80 levels
// added instead, so that even a black floor has texture.
Rgb floor_shade(Rgb floor, double f);

// The floor shade (floor_shade at the ends of the two ranges and x1.0) that falls in `t`, if any.
bool floor_shade_in(const fw::ColorThreshold& t, Rgb floor, double speckle, Rgb& shade_out,
                    double& factor_out);

}  // namespace carril::sim
