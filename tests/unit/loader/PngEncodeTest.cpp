// PNG bytes read back with libpng: every format, padded rows, and the refusals.
#include "loader/PngEncode.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <cstdint>
#include <vector>

namespace carril::loader {
namespace {

// The decoded pixels of `png` in `format` (libpng converts), with its size.
std::vector<std::uint8_t> decode(const std::string& png, png_uint_32 format, png_uint_32& w,
                                 png_uint_32& h) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_memory(&image, png.data(), png.size()) == 0) {
    ADD_FAILURE() << image.message;
    return {};
  }
  image.format = format;
  w = image.width;
  h = image.height;
  std::vector<std::uint8_t> out(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, out.data(), 0, nullptr) == 0) {
    ADD_FAILURE() << image.message;
  }
  return out;
}

TEST(PngEncodeTest, BgrRowsWithPaddingComeBackAsTheSamePixels) {
  // 5 x 3 BGR pixels in rows of 20 bytes (15 used): the padding must not leak into the image.
  constexpr int w = 5, h = 3, stride = 20;
  std::vector<std::uint8_t> bgr(std::size_t(stride) * h, 0xEE);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &bgr[std::size_t(y) * stride + 3 * std::size_t(x)];
      p[0] = std::uint8_t(10 * x);       // B
      p[1] = std::uint8_t(100 + y);      // G
      p[2] = std::uint8_t(200 + x + y);  // R
    }
  }
  std::string png;
  ASSERT_EQ(encode_png(bgr.data(), w, h, PngPixels::Bgr, stride, png), std::nullopt);
  png_uint_32 dw = 0, dh = 0;
  const auto rgb = decode(png, PNG_FORMAT_RGB, dw, dh);
  ASSERT_EQ(dw, png_uint_32(w));
  ASSERT_EQ(dh, png_uint_32(h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgb[(std::size_t(y) * w + std::size_t(x)) * 3];
      EXPECT_EQ(p[0], 200 + x + y) << x << "," << y;  // R back in first place
      EXPECT_EQ(p[1], 100 + y) << x << "," << y;
      EXPECT_EQ(p[2], 10 * x) << x << "," << y;
    }
  }
}

TEST(PngEncodeTest, GreyRgbAndBgraPackedRows) {
  const std::vector<std::uint8_t> grey = {0, 50, 100, 150, 200, 250};
  std::string png;
  ASSERT_EQ(encode_png(grey.data(), 3, 2, PngPixels::Gray, 0, png), std::nullopt);
  png_uint_32 w = 0, h = 0;
  EXPECT_EQ(decode(png, PNG_FORMAT_GRAY, w, h), grey);
  EXPECT_EQ(w, 3U);
  const std::vector<std::uint8_t> rgb = {1, 2, 3, 4, 5, 6};
  ASSERT_EQ(encode_png(rgb.data(), 2, 1, PngPixels::Rgb, 0, png), std::nullopt);
  EXPECT_EQ(decode(png, PNG_FORMAT_RGB, w, h), rgb);
  const std::vector<std::uint8_t> bgra = {1, 2, 3, 255, 4, 5, 6, 128};
  ASSERT_EQ(encode_png(bgra.data(), 2, 1, PngPixels::Bgra, 0, png), std::nullopt);
  EXPECT_EQ(decode(png, PNG_FORMAT_BGRA, w, h), bgra);
}

TEST(PngEncodeTest, NoPixelsIsAnErrorNotAnEmptyFile) {
  std::string png = "old";
  const std::uint8_t px[3] = {};
  auto err = encode_png(nullptr, 2, 2, PngPixels::Rgb, 0, png);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("PNG encoding failed: no pixels"), std::string::npos) << *err;
  err = encode_png(px, 0, 1, PngPixels::Rgb, 0, png);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("0 x 1"), std::string::npos) << *err;
}

}  // namespace
}  // namespace carril::loader
