#pragma once
// A convex polygon fill that writes exactly the bytes OpenCV 4.6's
// cv::fillConvexPoly(img, pts, n, color, cv::LINE_8, 4) writes on a continuous 8-bit 3-channel
// image: the same outline (each edge stepped in 16.16 fixed point, clipped to the image the
// same way) and the same scanline spans (the same rounding of vertex rows and edge slopes).
// It exists because the camera renderer fills thousands of small floor speckles per frame and
// OpenCV's per-call overhead (Mat and Scalar conversion, a vector allocation, code paths for
// every pixel size) cost more than the pixels. The oracle test (ConvexFillTest.cpp) compares
// it with the installed OpenCV on random polygons.
#include <cstdint>

namespace carril::sim {

// A polygon vertex in 1/16 pixel (kFillShift fractional bits); same layout as cv::Point.
struct FixedPt {
  int x, y;
};

inline constexpr int kFillShift = 4;  // fractional bits of FixedPt coordinates

// Fills the polygon pts[0..n) [1/16 px] with colour (b, g, r) on the continuous width x height
// BGR image `bgr` (3 bytes a pixel, rows packed), as cv::fillConvexPoly with LINE_8, shift 4.
void fill_convex_poly(std::uint8_t* bgr, int width, int height, const FixedPt* pts, int n,
                      std::uint8_t b, std::uint8_t g, std::uint8_t r);

// Fills pixels x0..x1 of rows y0..y1 (inclusive, clipped to the image) with colour (b, g, r), on
// the same kind of image as fill_convex_poly.
void fill_rect(std::uint8_t* bgr, int width, int height, int x0, int y0, int x1, int y1,
               std::uint8_t b, std::uint8_t g, std::uint8_t r);

}  // namespace carril::sim
