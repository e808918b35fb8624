#include "firmware/perception/FloorBox.hpp"

#include <cstring>

#include "firmware/perception/ColorClassifier.hpp"

namespace carril::fw {

namespace {
constexpr int kCells = 1 << color_lut::kBits;

// Whether the cells with channel `axis` at `at` and the other two in [lo, hi] are all clear.
bool face_clear(const std::uint8_t* lut, const int lo[3], const int hi[3], int axis, int at) {
  int a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = c == axis ? at : lo[c];
    b[c] = c == axis ? at : hi[c];
  }
  for (int x = a[0]; x <= b[0]; ++x) {
    for (int y = a[1]; y <= b[1]; ++y) {
      for (int z = a[2]; z <= b[2]; ++z) {
        if (lut[color_lut::index(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z))] != 0)
          return false;
      }
    }
  }
  return true;
}
}  // namespace

FloorBox FloorBox::grow(const std::uint8_t* lut, std::uint32_t seed, int max_width) {
  if (seed >= color_lut::kSize || lut[seed] != 0 || max_width < 1) return FloorBox{};
  constexpr std::uint32_t kMask = kCells - 1;
  const int s[3] = {int(seed >> (2 * color_lut::kBits)), int((seed >> color_lut::kBits) & kMask),
                    int(seed & kMask)};
  int lo[3] = {s[0], s[1], s[2]}, hi[3] = {s[0], s[1], s[2]};
  // A face that met a set cell stays where it is: checked again after the others grew it could
  // pass, but each retry would cost up to a face's reads.
  bool stuck_lo[3] = {false, false, false}, stuck_hi[3] = {false, false, false};
  for (bool grew = true; grew;) {
    grew = false;
    for (int c = 0; c < 3; ++c) {
      if (!stuck_lo[c] && hi[c] - lo[c] + 1 < max_width && lo[c] > 0) {
        stuck_lo[c] = !face_clear(lut, lo, hi, c, lo[c] - 1);
        if (!stuck_lo[c]) {
          --lo[c];
          grew = true;
        }
      }
      if (!stuck_hi[c] && hi[c] - lo[c] + 1 < max_width && hi[c] < kCells - 1) {
        stuck_hi[c] = !face_clear(lut, lo, hi, c, hi[c] + 1);
        if (!stuck_hi[c]) {
          ++hi[c];
          grew = true;
        }
      }
    }
  }
  std::uint8_t lo_bytes[3], hi_bytes[3];
  for (int c = 0; c < 3; ++c) {
    lo_bytes[c] = std::uint8_t(4 * lo[c]);
    hi_bytes[c] = std::uint8_t(4 * hi[c] + 3);
  }
  return of_bytes(lo_bytes, hi_bytes);
}

FloorBox FloorBox::of_bytes(const std::uint8_t lo[3], const std::uint8_t hi[3]) {
  FloorBox box;
  box.valid_ = true;
  for (int c = 0; c < 3; ++c) {
    box.lo_[c] = lo[c];
    box.hi_[c] = hi[c];
  }
  box.set_bounds();
  return box;
}

void FloorBox::set_bounds() {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 16; ++j) {
      vlo_[i][j] = lo_[(16 * i + j) % 3];
      vhi_[i][j] = hi_[(16 * i + j) % 3];
    }
  }
}

bool FloorBox::holds_run(const std::uint8_t* p, int row_bytes) const {
  static_assert(kRunBytes % 48 == 0, "whole groups of three loads");
  lanes::U8x16 mn[3], mx[3];
  for (int i = 0; i < 3; ++i) {
    mn[i] = ~lanes::U8x16{};
    mx[i] = lanes::U8x16{};
  }
  for (int o = 0; o < kRunBytes; o += 16) {
    lanes::U8x16 a, b;
    std::memcpy(&a, p + o, sizeof a);
    std::memcpy(&b, p + row_bytes + o, sizeof b);
    const int i = (o / 16) % 3;
    mn[i] = a < mn[i] ? a : mn[i];
    mn[i] = b < mn[i] ? b : mn[i];
    mx[i] = a > mx[i] ? a : mx[i];
    mx[i] = b > mx[i] ? b : mx[i];
  }
  auto out = (mn[0] < vlo_[0]) | (mx[0] > vhi_[0]);
  for (int i = 1; i < 3; ++i) out |= (mn[i] < vlo_[i]) | (mx[i] > vhi_[i]);
  std::uint64_t q[2];
  std::memcpy(q, &out, sizeof q);
  return (q[0] | q[1]) == 0;
}

bool FloorBox::clear_in(const std::uint8_t* lut) const {
  if (!valid_) return true;
  const int lo6[3] = {lo_[0] / 4, lo_[1] / 4, lo_[2] / 4};
  const int hi6[3] = {hi_[0] / 4, hi_[1] / 4, hi_[2] / 4};
  for (int x = lo6[0]; x <= hi6[0]; ++x) {
    if (!face_clear(lut, lo6, hi6, 0, x)) return false;
  }
  return true;
}

}  // namespace carril::fw
