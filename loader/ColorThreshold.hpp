#pragma once
// The tape detector's colour windows for a mission's colours, the same on the robot and in the
// simulator.
#include <string>

#include "firmware/perception/ColorClassifier.hpp"
#include "loader/MissionSpec.hpp"

namespace carril::loader {

// The detector's window for a mission colour: a named colour (white, black, red, green, blue,
// yellow) uses its firmware preset, an [r, g, b] colour a window round it
// (fw::threshold_around_rgb). `name` is MissionSpec::line_color_name / end_color_name.
fw::ColorThreshold detector_threshold(const std::string& name, Rgb c);

// True when the detector would classify `c` as inside `t`: the exact colour, or the colour its
// 6-bit lookup-table cell is classified by (fw::color_lut).
bool detector_sees(const fw::ColorThreshold& t, Rgb c);

}  // namespace carril::loader
