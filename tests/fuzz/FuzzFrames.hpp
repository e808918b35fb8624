#pragma once
// Binary fuzz inputs read front to back (so seed files are easy to write by hand: see
// make_seeds.py), and CAN frames from them: 13 bytes each, id (4, little-endian; bit 31
// extended, bit 30 remote request, bit 29 error), len (1, taken modulo 16, so lengths above 8
// reach the decoders as a bad frame would), data (8). Reads past the end give zeros.
#include <cstddef>
#include <cstdint>

#include "hal/CanBus.hpp"

namespace carril::fuzz {

class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  std::size_t remaining() const { return n_ - at_; }
  std::uint8_t u8() { return at_ < n_ ? p_[at_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(u8() | (u8() << 8)); }
  std::uint32_t u32() {
    const std::uint32_t lo = u16();
    return lo | (std::uint32_t{u16()} << 16);
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
  std::size_t at_ = 0;
};

inline hal::CanFrame read_frame(ByteReader& in) {
  hal::CanFrame f;
  const std::uint32_t raw = in.u32();
  f.extended = (raw & (1U << 31)) != 0;
  f.rtr = (raw & (1U << 30)) != 0;
  f.error = (raw & (1U << 29)) != 0;
  f.id = raw & (f.extended ? hal::kCanExtIdMask : hal::kCanStdIdMask);
  // Deliberately not clamped to 8: a decoder must not trust len (a bad driver or a fuzzed bus).
  f.len = static_cast<std::uint8_t>(in.u8() % 16);
  for (auto& b : f.data) b = in.u8();
  return f;
}

}  // namespace carril::fuzz
