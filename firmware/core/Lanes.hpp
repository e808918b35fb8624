#pragma once
// Byte and 16-bit lanes for pixel loops (perception, frame health) (GCC and Clang vector
// extensions: SSE2 on x86-64, NEON on aarch64). Written out so, the compiler neither falls back to
// a scalar loop for a short tail nor widens to 32-bit lanes.
#include <bit>
#include <cstdint>
#include <cstring>

namespace carril::fw::lanes {

using U8x8 = std::uint8_t __attribute__((vector_size(8)));
using U16x8 = std::uint16_t __attribute__((vector_size(16)));
using U8x16 = std::uint8_t __attribute__((vector_size(16)));
using U32x4 = std::uint32_t __attribute__((vector_size(16)));

// Eight bytes to eight lanes: each byte paired with a zero byte (one unpack instruction).
inline U16x8 widen8(const std::uint8_t* p) {
  static_assert(std::endian::native == std::endian::little, "byte pairs read as little-endian");
  U8x8 v;
  std::memcpy(&v, p, sizeof v);
  const U8x16 pairs =
      __builtin_shufflevector(v, U8x8{}, 0, 8, 1, 9, 2, 10, 3, 11, 4, 12, 5, 13, 6, 14, 7, 15);
  U16x8 r;
  std::memcpy(&r, &pairs, sizeof r);
  return r;
}
inline U16x8 load16(const std::uint16_t* p) {
  U16x8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store16(std::uint16_t* p, U16x8 v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace carril::fw::lanes
