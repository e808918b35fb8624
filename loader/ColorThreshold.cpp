#include "loader/ColorThreshold.hpp"

namespace carril::loader {

fw::ColorThreshold detector_threshold(const std::string& name, Rgb c) {
  fw::ColorThreshold t;
  if (fw::color_preset(name.c_str(), t)) return t;
  return fw::threshold_around_rgb(c.r, c.g, c.b);
}

bool detector_sees(const fw::ColorThreshold& t, Rgb c) {
  if (fw::in_threshold(t, fw::bgr_to_hsv8(c.b, c.g, c.r))) return true;
  // The lookup table classifies each 6-bit cell at its centre colour.
  auto centre = [](std::uint8_t v) { return 4 * (v >> 2) + 2; };
  return fw::in_threshold(t, fw::bgr_to_hsv8(centre(c.b), centre(c.g), centre(c.r)));
}

}  // namespace carril::loader
