#pragma once
// The tape detector's colour windows as the simulator configures them, and the check the loader
// makes with them: the floor, as rendered, must not look like the tape or the end mark, and the
// tape must not look like the end mark.
#include <string>

#include "firmware/perception/ColorClassifier.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// The detector's window for a mission colour: a named colour (white, black, red, green, blue,
// yellow) uses its firmware preset, an [r, g, b] colour a window round it
// (fw::threshold_around_rgb). `name` is MissionSpec::line_color_name / end_color_name.
fw::ColorThreshold detector_threshold(const std::string& name, Rgb c);

// The rendered floor's texture (host_sim/sensors/CameraRenderer) shades the floor colour by a
// factor in [kFloorShadeMin, kFloorShadeMax].
inline constexpr double kFloorShadeMin = 0.85;
inline constexpr double kFloorShadeMax = 1.15;

// The floor colour shaded by factor f: each channel times f, rounded, clamped to 255; a floor
// darker than 56 in every channel (where a factor would change little) gets (f - 1) * 80 levels
// added instead, so that even a black floor has texture.
Rgb floor_shade(Rgb floor, double f);

// True when the detector would classify `c` as inside `t`: the exact colour, or the colour its
// 6-bit lookup-table cell is classified by (fw::color_lut).
bool detector_sees(const fw::ColorThreshold& t, Rgb c);

// The floor shade (floor_shade at x0.85, x0.95, x1.0, x1.05 or x1.15) that falls in `t`, if any.
bool floor_shade_in(const fw::ColorThreshold& t, Rgb floor, Rgb& shade_out, double& factor_out);

}  // namespace carril::sim
