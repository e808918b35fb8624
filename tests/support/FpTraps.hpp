#pragma once
#include <cfenv>

namespace carril::test {

// Trap FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW (glibc's feenableexcept).
inline void enable_fp_traps() {
  feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
}

}  // namespace carril::test
