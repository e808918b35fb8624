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

// The rendered floor's texture scales each channel of the floor colour by a factor in
// [kFloorShadeMin, kFloorShadeMax] (clamped to 255).
inline constexpr double kFloorShadeMin = 0.85;
inline constexpr double kFloorShadeMax = 1.15;

// True when the detector would classify `c` as inside `t`: the exact colour, or the colour its
// 6-bit lookup-table cell is classified by (fw::color_lut).
bool detector_sees(const fw::ColorThreshold& t, Rgb c);

// The floor shade (x0.85, x1.0 or x1.15, each channel rounded down and up, clamped to 255)
// that falls in `t`, if any.
bool floor_shade_in(const fw::ColorThreshold& t, Rgb floor, Rgb& shade_out, double& factor_out);

}  // namespace carril::sim
