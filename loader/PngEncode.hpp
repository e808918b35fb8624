#pragma once
// 8-bit images to PNG bytes with libpng's simplified API, for every figure carril writes
// (costmaps here, the simulator's plots): host only, in library carril_costmap_png (the robot's
// cross build has no libpng). Not cv::imencode: OpenCV's codecs pull some 130 shared libraries
// into the simulator's start.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace carril::loader {

enum class PngPixels : std::uint8_t { Gray, Rgb, Bgr, Bgra };

// Encodes a width x height image of `pixels` rows `stride_bytes` apart (0: packed) into `png`.
// nullopt on success, else what went wrong ("PNG encoding failed: ...").
std::optional<std::string> encode_png(const std::uint8_t* pixels, int width, int height,
                                      PngPixels format, std::ptrdiff_t stride_bytes,
                                      std::string& png);

}  // namespace carril::loader
