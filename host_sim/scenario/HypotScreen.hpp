#pragma once
// Distance tests that take std::hypot only where the sum of squares leaves the answer in doubt
// (hypot is about 20 ns; the squares are two multiplies). Same answers as hypot, to the bit:
// the sum of squares and hypot are each within a few units in the last place (about 1e-16
// relative) of the true values, far inside the 1e-12 margin; outside [1e-100, 1e100] the squares
// could lose precision or overflow, and hypot decides.
#include <cmath>

namespace carril::sim {

namespace hypot_screen {
// Squares of these are within an ulp or so of the true values and cannot overflow.
inline bool fits(double dx, double dy, double d) {
  return d >= 1e-100 && d <= 1e100 && std::abs(dx) <= 1e100 && std::abs(dy) <= 1e100;
}
}  // namespace hypot_screen

// False only where std::hypot(dx, dy) <= d is certainly false.
inline bool hypot_may_be_below_or_at(double dx, double dy, double d) {
  return !hypot_screen::fits(dx, dy, d) || dx * dx + dy * dy <= d * d * (1.0 + 1e-12);
}

// std::hypot(dx, dy) <= limit.
inline bool hypot_at_most(double dx, double dy, double limit) {
  if (hypot_screen::fits(dx, dy, limit)) {
    const double d2 = dx * dx + dy * dy, l2 = limit * limit;
    if (d2 > l2 * (1.0 + 1e-12)) return false;
    if (d2 < l2 * (1.0 - 1e-12)) return true;
  }
  return std::hypot(dx, dy) <= limit;
}

}  // namespace carril::sim
