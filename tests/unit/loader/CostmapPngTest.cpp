// Costmap PNG figures, read back with libpng: size with the upscale factor, vertical flip, colours.
#include "loader/CostmapPng.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "tests/unit/loader/MapFileTestUtil.hpp"

namespace carril::loader {
namespace {

namespace cost = fw::cost;
using Rgb = std::array<std::uint8_t, 3>;

struct Image {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  Rgb at(std::uint32_t x, std::uint32_t y) const {
    const std::size_t i = (std::size_t{y} * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Image read_png(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Image out;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    ADD_FAILURE() << path << ": " << image.message;
    return out;
  }
  image.format = PNG_FORMAT_RGB;
  out.width = image.width;
  out.height = image.height;
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) == 0) {
    ADD_FAILURE() << path << ": " << image.message;
  }
  return out;
}

TEST(CostmapPng, ColoursFlipAndScale) {
  const auto dir = test::fresh_dir();
  const std::string path = (dir / "lab.png").string();
  // 3 x 2 cells, row-major from the lower-left.
  const std::array<std::uint8_t, 6> costs = {
      cost::kFree, cost::kUnknown, cost::kLethal, cost::kInscribed, 1, cost::kMaxGraded};
  ASSERT_EQ(export_costmap_png(path, costs.data(), {3, 2, 0.05, 0, 0}, 4), std::nullopt);
  EXPECT_EQ(test::list_dir(dir), std::vector<std::string>{"lab.png"});
  const Image img = read_png(path);
  ASSERT_EQ(img.width, 12U);
  ASSERT_EQ(img.height, 8U);
  // Top half = the map's row y=1; every pixel of a 4x4 block has the cell's colour.
  EXPECT_EQ(img.at(0, 0), costmap_png_rgb(cost::kInscribed));
  EXPECT_EQ(img.at(3, 3), costmap_png_rgb(cost::kInscribed));
  EXPECT_EQ(img.at(5, 2), costmap_png_rgb(1));
  EXPECT_EQ(img.at(11, 0), costmap_png_rgb(cost::kMaxGraded));
  EXPECT_EQ(img.at(0, 4), (Rgb{255, 255, 255}));  // free: white
  EXPECT_EQ(img.at(6, 7), (Rgb{128, 128, 128}));  // unknown: grey
  EXPECT_EQ(img.at(11, 7), (Rgb{0, 0, 0}));       // lethal: black
}

TEST(CostmapPng, GradedCostsDarkenFromYellowToOrange) {
  const Rgb low = costmap_png_rgb(1);
  const Rgb high = costmap_png_rgb(cost::kMaxGraded);
  EXPECT_EQ(low, (Rgb{255, 245, 170}));
  EXPECT_EQ(high, (Rgb{205, 110, 0}));
  for (int c = 2; c <= cost::kMaxGraded; ++c) {
    const Rgb a = costmap_png_rgb(static_cast<std::uint8_t>(c - 1));
    const Rgb b = costmap_png_rgb(static_cast<std::uint8_t>(c));
    EXPECT_LE(b[0] + b[1] + b[2], a[0] + a[1] + a[2]) << c;  // never lighter
  }
  EXPECT_NE(costmap_png_rgb(cost::kInscribed), high);
}

TEST(CostmapPng, BadInputIsNamed) {
  const auto dir = test::fresh_dir();
  const std::string path = (dir / "lab.png").string();
  const std::array<std::uint8_t, 1> one = {0};
  EXPECT_EQ(export_costmap_png(path, one.data(), {1, 1, 0.05, 0, 0}, 0),
            path + ": scale must be 1 to 16, got 0");
  EXPECT_EQ(export_costmap_png(path, nullptr, {1, 1, 0.05, 0, 0}),
            path + ": nothing to export (no costs, or nx 1, ny 1)");
  EXPECT_TRUE(test::list_dir(dir).empty());
}

}  // namespace
}  // namespace carril::loader
