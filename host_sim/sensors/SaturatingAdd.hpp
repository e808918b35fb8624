#pragma once
// Byte-wise saturating arithmetic over whole image rows, the inner loop of the camera's noise and
// glare: d[i] = clamp(d[i] + up[i] - down[i], 0, 255) where one of up[i], down[i] is 0. Sixteen
// bytes per SSE2 instruction where the host has SSE2 (every x86-64), plain C++ elsewhere; both
// give the same bytes. Host simulator only.
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace carril::sim {

// d[i] = min(d[i] + up[i], 255) for i < n.
inline void add_saturate(std::uint8_t* d, const std::uint8_t* up, std::size_t n) {
  std::size_t i = 0;
#if defined(__SSE2__)
  for (; i + 16 <= n; i += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(d + i));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(up + i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(d + i), _mm_adds_epu8(a, b));
  }
#endif
  for (; i < n; ++i) {
    const int v = int(d[i]) + int(up[i]);
    d[i] = static_cast<std::uint8_t>(v > 255 ? 255 : v);
  }
}

// d[i] = max(min(d[i] + up[i], 255) - down[i], 0) for i < n.
inline void add_sub_saturate(std::uint8_t* d, const std::uint8_t* up, const std::uint8_t* down,
                             std::size_t n) {
  std::size_t i = 0;
#if defined(__SSE2__)
  for (; i + 16 <= n; i += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(d + i));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(up + i));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(down + i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(d + i), _mm_subs_epu8(_mm_adds_epu8(a, b), c));
  }
#endif
  for (; i < n; ++i) {
    int v = int(d[i]) + int(up[i]);
    v = (v > 255 ? 255 : v) - int(down[i]);
    d[i] = static_cast<std::uint8_t>(v < 0 ? 0 : v);
  }
}

}  // namespace carril::sim
