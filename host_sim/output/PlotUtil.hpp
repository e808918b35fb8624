#pragma once
// Drawing helpers shared by the two plots (internal to carril_sim_output).
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim::plot {

inline cv::Scalar bgr(Rgb c) {
  return cv::Scalar(c.b, c.g, c.r);
}

// Hershey fonts draw ASCII only; other bytes become '?'.
std::string ascii(std::string_view s);

// Draws `text` with its baseline at `org`, shrinking the font (down to a floor) so that it fits
// in `max_width` pixels.
void put_text(cv::Mat& img, std::string_view text, cv::Point org, double scale, cv::Scalar color,
              int max_width = 0, int thickness = 1);

// Blends a filled rectangle into the image (legend and scale-bar backgrounds).
void shade_rect(cv::Mat& img, cv::Rect r, cv::Scalar color, double alpha);

// A step of 1, 2 or 5 times a power of ten giving about `target` intervals over `range` (> 0).
double nice_step(double range, int target);

// `%g` of v, with values within a hair of zero printed as 0 (no "-0", no "1e-17").
std::string tick_label(double v, double step);

// PNG bytes of `img` (8-bit grey, BGR or BGRA; loader::encode_png); false with `error` set.
bool encode_png(const cv::Mat& img, std::string& png, std::string& error);

}  // namespace carril::sim::plot
