#pragma once
// Cell costs with Nav2's semantics, so plots, saved maps and planners agree with ROS tools.
#include <cstdint>

namespace carril::fw::cost {

constexpr std::uint8_t kFree = 0;         // nothing known against driving here
constexpr std::uint8_t kMaxGraded = 252;  // highest graded (passable) cost
constexpr std::uint8_t kInscribed = 253;  // the footprint's inscribed circle would touch lethal
constexpr std::uint8_t kLethal = 254;     // occupied or not traversable
constexpr std::uint8_t kUnknown = 255;    // never observed

// Passable for a robot whose centre is on the cell (free or graded).
constexpr bool passable(std::uint8_t c) {
  return c <= kMaxGraded;
}

}  // namespace carril::fw::cost
