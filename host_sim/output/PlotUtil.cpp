#include "host_sim/output/PlotUtil.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "loader/PngEncode.hpp"

namespace carril::sim::plot {

std::string ascii(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f) c = '?';
  }
  return out;
}

void put_text(cv::Mat& img, std::string_view text, cv::Point org, double scale, cv::Scalar color,
              int max_width, int thickness) {
  const std::string t = ascii(text);
  if (max_width > 0) {
    int baseline = 0;
    while (scale > 0.3 &&
           cv::getTextSize(t, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline).width >
               max_width) {
      scale *= 0.9;
    }
  }
  cv::putText(img, t, org, cv::FONT_HERSHEY_SIMPLEX, scale, color, thickness, cv::LINE_AA);
}

void shade_rect(cv::Mat& img, cv::Rect r, cv::Scalar color, double alpha) {
  r &= cv::Rect(0, 0, img.cols, img.rows);
  if (r.area() <= 0) return;
  cv::Mat roi = img(r);
  cv::Mat fill(roi.size(), roi.type(), color);
  cv::addWeighted(fill, alpha, roi, 1.0 - alpha, 0.0, roi);
}

double nice_step(double range, int target) {
  const double raw = range / std::max(1, target);
  if (!(raw > 0.0) || !std::isfinite(raw)) return 1.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double f = norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0;
  return f * mag;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) < std::abs(step) * 1e-6) v = 0.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool encode_png(const cv::Mat& img, std::string& png, std::string& error) {
  if (img.depth() != CV_8U || (img.channels() != 1 && img.channels() != 3 && img.channels() != 4)) {
    error = "PNG encoding failed: not an 8-bit grey, BGR or BGRA image";
    return false;
  }
  const loader::PngPixels format = img.channels() == 1   ? loader::PngPixels::Gray
                                   : img.channels() == 3 ? loader::PngPixels::Bgr
                                                         : loader::PngPixels::Bgra;
  if (auto err = loader::encode_png(img.data, img.cols, img.rows, format,
                                    static_cast<std::ptrdiff_t>(img.step[0]), png)) {
    error = *err;
    return false;
  }
  return true;
}

}  // namespace carril::sim::plot
