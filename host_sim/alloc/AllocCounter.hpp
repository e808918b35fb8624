#pragma once
// Counts heap allocations made inside "windows" (the firmware's ticks), for the simulator and for
// the tests (the aarch64 cross build's included: it is built without the simulator). Linking
// carril_alloc_counter replaces global operator new (every form) with a counting version, and
// with glibc and without AddressSanitizer malloc, calloc, realloc, memalign, aligned_alloc,
// posix_memalign, valloc and pvalloc too (the way ArduPilot wraps malloc). Outside a window a
// count costs one increment.
#include <cstdint>

namespace carril::alloc {

// Open/close a window; allocations between are counted. Not reentrant; one thread.
void begin_window();
void end_window();
// Allocations counted in all windows so far.
std::uint64_t count_in_windows();
// Allocations anywhere since start (sanity check that counting is live).
std::uint64_t count_total();
// True when malloc and its family are counted too (glibc, no AddressSanitizer, which owns
// malloc; then only operator new is counted).
bool counts_malloc();

}  // namespace carril::alloc
