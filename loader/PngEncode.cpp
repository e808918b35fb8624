#include "loader/PngEncode.hpp"

#include <png.h>

namespace carril::loader {

std::optional<std::string> encode_png(const std::uint8_t* pixels, int width, int height,
                                      PngPixels format, std::ptrdiff_t stride_bytes,
                                      std::string& png) {
  if (pixels == nullptr || width <= 0 || height <= 0) {
    return "PNG encoding failed: no pixels (" + std::to_string(width) + " x " +
           std::to_string(height) + ")";
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  switch (format) {
    case PngPixels::Gray:
      image.format = PNG_FORMAT_GRAY;
      break;
    case PngPixels::Rgb:
      image.format = PNG_FORMAT_RGB;
      break;
    case PngPixels::Bgr:
      image.format = PNG_FORMAT_BGR;
      break;
    case PngPixels::Bgra:
      image.format = PNG_FORMAT_BGRA;
      break;
  }
  // In components, which for 8-bit samples are bytes; 0 = packed rows.
  const auto stride = static_cast<png_int_32>(stride_bytes);
  // The first call sizes the buffer, the second writes into it.
  png_alloc_size_t size = 0;
  for (int pass = 0; pass < 2; ++pass) {
    void* out = pass == 0 ? nullptr : png.data();
    if (png_image_write_to_memory(&image, out, &size, 0, pixels, stride, nullptr) == 0) {
      const std::string msg = image.message;
      png_image_free(&image);
      return "PNG encoding failed: libpng: " + msg;
    }
    if (pass == 0) png.assign(size, '\0');
  }
  png.resize(size);
  return std::nullopt;
}

}  // namespace carril::loader
