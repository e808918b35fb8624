#pragma once
// Floating-point traps for the simulator and the tests (host only: glibc feenableexcept), so a
// NaN or an overflow born in a run stops it where it happens.
#include <cfenv>

namespace carril::sim {

// Trap FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW (glibc's feenableexcept).
inline void enable_fp_traps() {
  feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
}

}  // namespace carril::sim
