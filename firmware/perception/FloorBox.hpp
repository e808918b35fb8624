#pragma once
// A box of colours round the floor's that the colour table (ColorClassifier.hpp) sends to
// neither the tape nor the end mark. LineDetector tests runs of sampled blocks against it with a
// few byte-wise minimums and maximums: a run whose every byte lies inside needs no table lookup,
// because every block average of such bytes quantises into the box. Which colours the box holds
// changes only the speed, never a verdict: every cell in it is a cell the table clears.
#include <cstdint>

#include "firmware/core/Lanes.hpp"

namespace carril::fw {

class FloorBox {
 public:
  // Bytes in a run: 48 pixels of a row (a multiple of 48, so each 16-byte load of a run keeps
  // its channel phase), i.e. eight blocks of 2 x 2 px every third block.
  static constexpr int kRunBytes = 144;

  // The box of 6-bit cells grown from cell `seed` (a color_lut index) of `lut` one face at a
  // time while the new face's cells are all clear, each side at most `max_width` cells; invalid
  // when the seed cell itself is set. At most max_width^3 + 6 max_width^2 table reads.
  static FloorBox grow(const std::uint8_t* lut, std::uint32_t seed, int max_width);
  // A box of the byte bounds lo[c]..hi[c] (B, G, R) as given (for the tests).
  static FloorBox of_bytes(const std::uint8_t lo[3], const std::uint8_t hi[3]);

  bool valid() const { return valid_; }
  // Byte bounds of channel c (B, G, R), inclusive: 4 x the 6-bit cell bounds, and 4 x + 3 above.
  std::uint8_t lo(int c) const { return lo_[c]; }
  std::uint8_t hi(int c) const { return hi_[c]; }
  // Whether bytes 0..kRunBytes-1 of the two rows at p and p + row_bytes (p on a pixel's first
  // byte) all lie in the box, channel by channel.
  bool holds_run(const std::uint8_t* p, int row_bytes) const;
  // Whether every cell of the box is clear in `lut` (what grow() guarantees; for the tests).
  bool clear_in(const std::uint8_t* lut) const;

 private:
  void set_bounds();

  bool valid_ = false;
  std::uint8_t lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
  // The bounds for the three loads of every 48 bytes: byte j of load i is channel (16i + j) % 3.
  lanes::U8x16 vlo_[3] = {}, vhi_[3] = {};
};

}  // namespace carril::fw
