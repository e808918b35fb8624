// FloorBox: the box grown round a floor colour holds only cells the colour table clears, holds
// the seed, keeps to its width, and stops at the first set cell in its way.
#include "firmware/perception/FloorBox.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "firmware/perception/ColorClassifier.hpp"
#include "firmware/perception/LineDetector.hpp"

namespace carril::test {
namespace {

using fw::FloorBox;
namespace lut = fw::color_lut;

std::vector<std::uint8_t> table(const char* line, const char* end) {
  fw::ColorThreshold a, b;
  EXPECT_TRUE(fw::color_preset(line, a));
  EXPECT_TRUE(fw::color_preset(end, b));
  std::vector<std::uint8_t> t(lut::kSize);
  lut::build(a, b, t.data());
  return t;
}

// The box's 6-bit cell bounds.
void cells(const FloorBox& b, int lo[3], int hi[3]) {
  for (int c = 0; c < 3; ++c) {
    lo[c] = b.lo(c) / 4;
    hi[c] = b.hi(c) / 4;
    EXPECT_EQ(b.lo(c) % 4, 0);
    EXPECT_EQ(b.hi(c) % 4, 3);
  }
}

TEST(FloorBoxTest, GrownBoxesHoldOnlyClearCellsAndTheirSeed) {
  const char* pairs[][2] = {
      {"white", "yellow"}, {"red", "yellow"}, {"black", "yellow"}, {"blue", "green"}};
  int boxes = 0;
  for (const auto& p : pairs) {
    SCOPED_TRACE(p[0]);
    const std::vector<std::uint8_t> t = table(p[0], p[1]);
    // Seeds over the whole cube, every 7th level a channel.
    for (std::uint32_t b = 0; b < 64; b += 7) {
      for (std::uint32_t g = 0; g < 64; g += 7) {
        for (std::uint32_t r = 0; r < 64; r += 7) {
          const std::uint32_t seed = lut::index(b, g, r);
          const FloorBox box = FloorBox::grow(t.data(), seed, 32);
          if (t[seed] != 0) {
            EXPECT_FALSE(box.valid()) << b << " " << g << " " << r;
            continue;
          }
          ASSERT_TRUE(box.valid());
          ++boxes;
          ASSERT_TRUE(box.clear_in(t.data())) << b << " " << g << " " << r;
          int lo[3], hi[3];
          cells(box, lo, hi);
          const std::uint32_t s[3] = {b, g, r};
          for (int c = 0; c < 3; ++c) {
            EXPECT_LE(lo[c], int(s[c]));
            EXPECT_GE(hi[c], int(s[c]));
            EXPECT_LE(hi[c] - lo[c] + 1, 32);
          }
        }
      }
    }
  }
  EXPECT_GT(boxes, 1000);
}

// A table clear but for one cell: the box grows to its width on every side the cell is not in
// the way of, and never over the cell.
TEST(FloorBoxTest, StopsAtASetCellAndKeepsToItsWidth) {
  std::vector<std::uint8_t> t(lut::kSize, 0);
  t[lut::index(30, 20, 20)] = lut::kLine;
  const FloorBox box = FloorBox::grow(t.data(), lut::index(20, 20, 20), 64);
  ASSERT_TRUE(box.valid());
  EXPECT_TRUE(box.clear_in(t.data()));
  int lo[3], hi[3];
  cells(box, lo, hi);
  EXPECT_EQ(hi[0], 29);  // blue stops under the set cell
  EXPECT_EQ(lo[0], 0);
  for (int c = 1; c < 3; ++c) {
    EXPECT_EQ(lo[c], 0);
    EXPECT_EQ(hi[c], 63);
  }
  const FloorBox narrow = FloorBox::grow(t.data(), lut::index(20, 20, 20), 8);
  cells(narrow, lo, hi);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(hi[c] - lo[c] + 1, 8);
  EXPECT_FALSE(FloorBox::grow(t.data(), lut::index(30, 20, 20), 32).valid());  // a set seed
}

// clear_in() itself can fail: a box over a set cell.
TEST(FloorBoxTest, ClearInFindsASetCellInside) {
  std::vector<std::uint8_t> t(lut::kSize, 0);
  t[lut::index(10, 11, 12)] = lut::kEnd;
  const std::uint8_t lo[3] = {4 * 8, 4 * 8, 4 * 8}, hi[3] = {4 * 12 + 3, 4 * 12 + 3, 4 * 12 + 3};
  const FloorBox box = FloorBox::of_bytes(lo, hi);
  EXPECT_FALSE(box.clear_in(t.data()));
  t[lut::index(10, 11, 12)] = 0;
  EXPECT_TRUE(box.clear_in(t.data()));
}

// holds_run() against a byte-by-byte reference: runs inside the box, each with one byte moved
// just outside (every byte position of both rows, below and above), at two row offsets.
TEST(FloorBoxTest, HoldsRunIsEveryBytesChannelTest) {
  const std::uint8_t lo[3] = {40, 60, 80}, hi[3] = {103, 123, 143};
  const FloorBox box = FloorBox::of_bytes(lo, hi);
  constexpr int kRowBytes = 640 * 3, kRun = FloorBox::kRunBytes;
  std::vector<std::uint8_t> img(2 * kRowBytes, 0);
  std::uint32_t state = 12345;
  const auto next = [&state] {
    state = state * 1664525U + 1013904223U;
    return state >> 8;
  };
  int inside = 0, outside = 0, wrong = 0;
  for (const int start : {0, 3 * 101}) {  // a run starts on a pixel
    for (int pos = -1; pos < 2 * kRun; ++pos) {
      for (const bool above : {false, true}) {
        // Every byte of both rows' runs in its channel's bounds (the channel of byte k is k % 3).
        for (int row = 0; row < 2; ++row) {
          for (int k = 0; k < kRun; ++k) {
            const int c = k % 3;
            img[std::size_t(row * kRowBytes + start + k)] =
                std::uint8_t(lo[c] + int(next() % unsigned(hi[c] - lo[c] + 1)));
          }
        }
        if (pos >= 0) {  // then one byte one level outside
          const int row = pos / kRun, k = pos % kRun, c = k % 3;
          img[std::size_t(row * kRowBytes + start + k)] =
              above ? std::uint8_t(hi[c] + 1) : std::uint8_t(lo[c] - 1);
        }
        const bool expected = pos < 0;
        const bool got = box.holds_run(img.data() + start, kRowBytes);
        wrong += got != expected ? 1 : 0;
        (got ? inside : outside) += 1;
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(inside, 4);
  EXPECT_EQ(outside, 2 * 2 * 2 * FloorBox::kRunBytes);
}

}  // namespace
}  // namespace carril::test
