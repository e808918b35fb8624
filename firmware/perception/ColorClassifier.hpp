#pragma once
// Colour classification for the tape detector, in HSV with OpenCV's 8-bit convention (H 0..179,
// S and V 0..255). The HSV of a colour is computed the way cv::cvtColor(COLOR_BGR2HSV) does for
// 8-bit images: integer arithmetic with reciprocal tables, no division per pixel. Per frame the
// detector does not even do that: it looks each block-averaged colour up in a table built once at
// construction (6 bits per channel, 256 KiB), whose entries hold both masks' bits.
#include <cstddef>
#include <cstdint>

#include "firmware/perception/LineDetector.hpp"

namespace carril::fw {

struct Hsv8 {
  int h = 0, s = 0, v = 0;  // H 0..179, S 0..255, V 0..255
};

namespace hsv_detail {
constexpr int kShift = 12;
// OpenCV's reciprocal tables: sdiv[v] = round(255 * 2^12 / v), hdiv[d] = round(180 * 2^12 / 6d).
struct Tables {
  int sdiv[256] = {};
  int hdiv[256] = {};
  constexpr Tables() {
    for (int i = 1; i < 256; ++i) {
      sdiv[i] = (2 * (255 << kShift) + i) / (2 * i);
      hdiv[i] = (2 * (180 << kShift) + 6 * i) / (12 * i);
    }
  }
};
inline constexpr Tables kTables{};
}  // namespace hsv_detail

// cv::cvtColor(COLOR_BGR2HSV) for one 8-bit colour.
inline Hsv8 bgr_to_hsv8(int b, int g, int r) {
  using namespace hsv_detail;
  const int v = b > g ? (b > r ? b : r) : (g > r ? g : r);
  const int vmin = b < g ? (b < r ? b : r) : (g < r ? g : r);
  const int diff = v - vmin;
  Hsv8 out;
  out.v = v;
  out.s = (diff * kTables.sdiv[v] + (1 << (kShift - 1))) >> kShift;
  int h = v == r ? g - b : (v == g ? b - r + 2 * diff : r - g + 4 * diff);
  h = (h * kTables.hdiv[diff] + (1 << (kShift - 1))) >> kShift;
  out.h = h < 0 ? h + 180 : h;
  return out;
}

// cv::inRange on the HSV window, both ends inclusive; h_lo > h_hi wraps round 180.
inline bool in_threshold(const ColorThreshold& t, const Hsv8& c) {
  const bool h_ok =
      t.h_lo <= t.h_hi ? (c.h >= t.h_lo && c.h <= t.h_hi) : (c.h >= t.h_lo || c.h <= t.h_hi);
  return h_ok && c.s >= t.s_lo && c.s <= t.s_hi && c.v >= t.v_lo && c.v <= t.v_hi;
}

// Lookup table from a colour quantised to 6 bits per channel to the mask bits.
namespace color_lut {
constexpr int kBits = 6;
constexpr std::size_t kSize = std::size_t{1} << (3 * kBits);
constexpr std::uint8_t kLine = 1;  // the tape colour
constexpr std::uint8_t kEnd = 2;   // the end-mark colour

// Fills `table` (kSize bytes). Each cell is classified at its centre colour (4 q + 2 for the
// quantised value q of each channel), so the table decides within 2 levels of the exact colour.
void build(const ColorThreshold& line, const ColorThreshold& end, std::uint8_t* table);

// Index from 6-bit quantised channels.
inline std::uint32_t index(std::uint32_t b6, std::uint32_t g6, std::uint32_t r6) {
  return (b6 << (2 * kBits)) | (g6 << kBits) | r6;
}
}  // namespace color_lut

}  // namespace carril::fw
