#include "firmware/perception/ColorClassifier.hpp"

#include <cstring>

namespace carril::fw {

namespace {

std::uint8_t u8(int v) {
  return static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
}

ColorThreshold window(int h_lo, int h_hi, int s_lo, int s_hi, int v_lo, int v_hi) {
  ColorThreshold t;
  t.h_lo = u8(h_lo);
  t.h_hi = u8(h_hi);
  t.s_lo = u8(s_lo);
  t.s_hi = u8(s_hi);
  t.v_lo = u8(v_lo);
  t.v_hi = u8(v_hi);
  return t;
}

}  // namespace

bool color_preset(const char* name, ColorThreshold& out) {
  if (name == nullptr) return false;
  // Tape colours as printed tape looks on a grey floor under the thesis's lighting: the chromatic
  // windows are +-10..20 hue steps round the pure hue with saturation and value at least ~40%;
  // white is bright and unsaturated, black is dark whatever its hue.
  struct Preset {
    const char* name;
    ColorThreshold t;
  };
  const Preset presets[] = {
      {"white", window(0, 179, 0, 60, 170, 255)},  {"black", window(0, 179, 0, 255, 0, 70)},
      {"red", window(170, 10, 100, 255, 70, 255)}, {"yellow", window(20, 35, 100, 255, 100, 255)},
      {"green", window(45, 85, 80, 255, 60, 255)}, {"blue", window(100, 130, 100, 255, 60, 255)},
  };
  for (const Preset& p : presets) {
    if (std::strcmp(name, p.name) == 0) {
      out = p.t;
      return true;
    }
  }
  return false;
}

ColorThreshold threshold_around_rgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const Hsv8 c = bgr_to_hsv8(b, g, r);
  if (c.s < 60) {
    // Nearly grey: any hue, low saturation, value within 70 levels.
    return window(0, 179, 0, c.s + 60, c.v - 70, c.v + 70);
  }
  // Chromatic: hue +-10 steps (wrapping round 180), saturation and value from 40% of the colour's
  // own (the darker, paler edges of the tape) up to the top.
  const int h_lo = c.h >= 10 ? c.h - 10 : c.h + 170;
  const int h_hi = c.h + 10 <= 179 ? c.h + 10 : c.h - 170;
  const int s_lo = c.s * 2 / 5 > 60 ? c.s * 2 / 5 : 60;
  const int v_lo = c.v * 2 / 5 > 50 ? c.v * 2 / 5 : 50;
  return window(h_lo, h_hi, s_lo, 255, v_lo, 255);
}

namespace color_lut {

void build(const ColorThreshold& line, const ColorThreshold& end, std::uint8_t* table) {
  constexpr std::uint32_t n = 1U << kBits;
  for (std::uint32_t b = 0; b < n; ++b) {
    for (std::uint32_t g = 0; g < n; ++g) {
      for (std::uint32_t r = 0; r < n; ++r) {
        const Hsv8 c = bgr_to_hsv8(int(4 * b + 2), int(4 * g + 2), int(4 * r + 2));
        std::uint8_t bits = 0;
        if (in_threshold(line, c)) bits |= kLine;
        if (in_threshold(end, c)) bits |= kEnd;
        table[index(b, g, r)] = bits;
      }
    }
  }
}

}  // namespace color_lut

}  // namespace carril::fw
