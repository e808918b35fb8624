#pragma once
// Counts heap allocations made inside "windows" (the firmware's ticks). Linking this library
// replaces global operator new/delete and malloc/calloc/realloc/memalign/aligned_alloc/
// posix_memalign/valloc/pvalloc with counting
// versions (the way ArduPilot wraps malloc); outside a window they cost one branch.
#include <cstdint>

namespace carril::alloc {

// Open/close a window; allocations between are counted. Not reentrant; one thread.
void begin_window();
void end_window();
// Allocations counted in all windows so far.
std::uint64_t count_in_windows();
// Allocations anywhere since start (sanity check that counting is live).
std::uint64_t count_total();
// True when malloc itself is replaced (false under AddressSanitizer, which owns malloc; then
// only operator new is counted).
bool counts_malloc();

}  // namespace carril::alloc
