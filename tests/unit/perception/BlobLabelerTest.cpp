// The bit-packed 3x3 erosion and dilation against a per-cell reference (cv::erode / cv::dilate
// borders: outside counts as set for erosion, clear for dilation), on masks that are empty, full,
// random and sparse (a few set rows, as the detector's masks are), in place and not.
#include "firmware/perception/BitRuns.hpp"
#include "firmware/perception/BlobLabeler.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace carril::test {
namespace {

using fw::BitImage;

struct Mask {
  Mask(int w, int h) : words(std::size_t(fw::bit_stride(w)) * std::size_t(h) + 1, 0) {
    img = {words.data(), w, h, fw::bit_stride(w)};
  }
  bool get(int x, int y) const { return (img.row(y)[x / 64] >> (x % 64)) & 1U; }
  void set(int x, int y) { img.row(y)[x / 64] |= std::uint64_t{1} << (x % 64); }
  std::vector<std::uint64_t> words;
  BitImage img;
};

// Per cell: min (erode) or max (dilate) over the 3x3 neighbourhood with the border value.
bool reference(const Mask& m, int x, int y, bool erode) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int u = x + dx, v = y + dy;
      const bool inside = u >= 0 && v >= 0 && u < m.img.width && v < m.img.height;
      const bool bit = inside ? m.get(u, v) : erode;
      if (erode && !bit) return false;
      if (!erode && bit) return true;
    }
  }
  return erode;
}

// The filtered mask equals the reference cell by cell, and no bit beyond the width is set.
void expect_filter(const Mask& src, bool erode, bool in_place, std::uint64_t garbage) {
  const int w = src.img.width, h = src.img.height;
  Mask out(w, h), tmp(w, h), copy = src;
  copy.img.bits = copy.words.data();
  for (auto& word : tmp.words) word = garbage;  // scratch starts dirty
  for (auto& word : out.words) word = garbage;  // and so does a separate output
  const BitImage& dst = in_place ? copy.img : out.img;
  if (erode) {
    fw::erode3x3(copy.img, dst, tmp.img);
  } else {
    fw::dilate3x3(copy.img, dst, tmp.img);
  }
  Mask result = in_place ? copy : out;
  result.img.bits = result.words.data();
  int wrong = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) wrong += result.get(x, y) != reference(src, x, y, erode);
    const int s = result.img.stride;
    if (w % 64 != 0) {
      wrong += (result.img.row(y)[s - 1] >> (w % 64)) != 0;  // padding stays clear
    }
  }
  EXPECT_EQ(wrong, 0) << (erode ? "erode" : "dilate") << " " << w << "x" << h
                      << (in_place ? " in place" : "");
}

TEST(BitMorphologyTest, ErosionAndDilationEqualAPerCellReference) {
  std::mt19937 rng(11);
  const int sizes[][2] = {{1, 1}, {5, 3}, {64, 4}, {65, 7}, {130, 9}, {320, 240}, {200, 1}};
  for (const auto& wh : sizes) {
    const int w = wh[0], h = wh[1];
    for (int kind = 0; kind < 6; ++kind) {
      Mask m(w, h);
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const bool on = kind == 1   ? true
                          : kind == 2 ? rng() % 2 == 0
                          : kind == 3 ? rng() % 8 != 0
                          : kind == 4 ? (y == h / 2 && x > w / 4 && x < w / 2)
                          : kind == 5 ? ((y == 0 || y == h - 1) && x % 3 != 0)
                                      : false;
          if (on) m.set(x, y);
        }
      }
      for (const bool erode : {true, false}) {
        for (const bool in_place : {true, false}) {
          expect_filter(m, erode, in_place, kind % 2 == 0 ? ~std::uint64_t{0} : 0x5A5AULL);
        }
      }
    }
  }
}

// A band of rows in the middle of a tall mask (the detector's usual case): both filters see the
// rows next to the band, which the row-range shortcut must not leave stale.
TEST(BitMorphologyTest, ABandOfRowsFiltersAsTheWholeMaskWould) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    const int w = 70 + int(rng() % 200), h = 20 + int(rng() % 60);
    const int y0 = int(rng() % std::uint32_t(h)), y1 = y0 + int(rng() % 4);
    Mask m(w, h);
    for (int y = y0; y <= y1 && y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        if (rng() % 3 != 0) m.set(x, y);
      }
    }
    for (const bool erode : {true, false}) expect_filter(m, erode, trial % 2 == 0, ~0ULL);
  }
}

// The horizontal pass over a range of words (the refiner's window) writes what the whole row's
// pass writes there, reading the words either side: rows of 1 to 6 words, every range, rows whose
// last word is partly outside the image, edge bits set and clear.
TEST(BitMorphologyTest, TheHorizontalPassOverARangeOfWordsEqualsTheWholeRowsThere) {
  std::mt19937_64 rng(12);
  int ranges = 0;
  for (int s = 1; s <= 6; ++s) {
    for (const int width : {64 * s, 64 * s - 1, 64 * s - 37}) {
      const std::uint64_t last = fw::bits::valid_bits(width, s - 1);
      for (int trial = 0; trial < 40; ++trial) {
        std::vector<std::uint64_t> row(static_cast<std::size_t>(s));
        for (std::uint64_t& w : row) {
          // Dense, sparse, and words with only their edge bits set or clear.
          const int kind = int(rng() % 4);
          w = kind == 0   ? rng()
              : kind == 1 ? (rng() & rng() & rng())
              : kind == 2 ? 0x8000000000000001ULL
                          : ~0x8000000000000001ULL;
        }
        row.back() &= last;
        for (const bool erode : {true, false}) {
          std::vector<std::uint64_t> whole(static_cast<std::size_t>(s)),
              part(static_cast<std::size_t>(s), 0x5A5A5A5A5A5A5A5AULL);
          if (erode) {
            fw::bits::hpass3<true>(row.data(), s, last, whole.data());
          } else {
            fw::bits::hpass3<false>(row.data(), s, last, whole.data());
          }
          for (int ka = 0; ka < s; ++ka) {
            for (int kb = ka; kb < s; ++kb) {
              if (erode) {
                fw::bits::hpass3<true>(row.data(), s, last, part.data(), ka, kb);
              } else {
                fw::bits::hpass3<false>(row.data(), s, last, part.data(), ka, kb);
              }
              for (int k = ka; k <= kb; ++k) {
                ASSERT_EQ(part[std::size_t(k)], whole[std::size_t(k)])
                    << "s " << s << " width " << width << " words " << ka << ".." << kb << " word "
                    << k << (erode ? " erode" : " dilate");
              }
              ++ranges;
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(ranges, 3 * 40 * 2 * (1 + 3 + 6 + 10 + 15 + 21));
}

}  // namespace
}  // namespace carril::test
