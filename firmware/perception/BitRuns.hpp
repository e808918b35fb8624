#pragma once
// Bit-packed mask rows (64 cells per word, bit i of word k is cell 64k + i): the helpers the
// blob labeller and refiner share.
#include <bit>
#include <cstdint>

namespace carril::fw::bits {

constexpr std::uint64_t kAll = ~std::uint64_t{0};

// Bits of word k that are cells of a `width`-wide row.
inline std::uint64_t valid_bits(int width, int k) {
  const int rem = width - 64 * k;
  return rem >= 64 ? kAll : ((std::uint64_t{1} << rem) - 1);
}

// Sets cells a..b (inclusive, a <= b) of a bit row.
inline void set_range(std::uint64_t* row, int a, int b) {
  const int ka = a >> 6, kb = b >> 6;
  for (int k = ka; k <= kb; ++k) {
    const int lo = k == ka ? (a & 63) : 0, hi = k == kb ? (b & 63) : 63;
    row[k] |= (kAll << lo) & (kAll >> (63 - hi));
  }
}

// 3-wide AND (erode) or OR (dilate) of a row of s words into out: the horizontal pass of a 3x3
// erosion or dilation. Cells outside the row count as set for erosion, clear for dilation (as
// cv::erode and cv::dilate's default border); `last` marks the valid bits of the last word.
// Only words ka..kb of out are written (0 <= ka <= kb < s; the whole row by default); they
// read the words either side.
template <bool kErode>
void hpass3(const std::uint64_t* r, int s, std::uint64_t last, std::uint64_t* out, int ka = 0,
            int kb = -1) {
  const std::uint64_t fill = kErode ? kAll : 0;
  if (kb < 0) kb = s - 1;
  // Word j of the row, the bits past its last cell as outside the row.
  const auto word = [&](int j) { return r[j] | (j == s - 1 ? (fill & ~last) : 0); };
  std::uint64_t prev = ka > 0 ? word(ka - 1) : fill;
  std::uint64_t cur = word(ka);
  for (int k = ka; k <= kb; ++k) {
    const std::uint64_t next = k + 1 < s ? word(k + 1) : fill;
    const std::uint64_t left = (cur << 1) | (prev >> 63);   // bit x holds cell x - 1
    const std::uint64_t right = (cur >> 1) | (next << 63);  // bit x holds cell x + 1
    out[k] = kErode ? (cur & left & right) : (cur | left | right);
    prev = cur;
    cur = next;
  }
}

// Finds runs of set cells along a row fed one word at a time, left to right.
class RunScanner {
 public:
  // Word k of the row: calls on_run(first, last) for each run that ends inside it. on_run returns
  // false to stop; word() then returns false too.
  template <typename OnRun>
  bool word(std::uint64_t w, int k, OnRun&& on_run) {
    for (int pos = 0;;) {
      const std::uint64_t look = (in_ ? ~w : w) & (kAll << pos);
      if (look == 0) return true;
      pos = std::countr_zero(look);
      if (!in_) {
        start_ = 64 * k + pos;
        in_ = true;
        continue;
      }
      in_ = false;
      if (!on_run(start_, 64 * k + pos - 1)) return false;
    }
  }
  // End of the row at cell `last`: a run still open ends there.
  template <typename OnRun>
  bool finish(int last, OnRun&& on_run) {
    if (!in_) return true;
    in_ = false;
    return on_run(start_, last);
  }

 private:
  bool in_ = false;
  int start_ = 0;
};

}  // namespace carril::fw::bits
