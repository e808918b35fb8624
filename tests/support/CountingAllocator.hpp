#pragma once
// Counts heap allocations made inside "windows" (the firmware's ticks), for test binaries that
// must run anywhere the firmware runs (the aarch64 cross build included), without the simulator.
// Linking carril_test_alloc_counter replaces global operator new (every form) with a counting
// version; with glibc and without AddressSanitizer, malloc, calloc, realloc, aligned_alloc and
// posix_memalign too. Outside a window a count costs one increment.
#include <cstdint>

namespace carril::test::alloc {

// Open/close a window; allocations between are counted. Not reentrant; one thread.
void begin_window();
void end_window();
// Allocations counted in all windows so far.
std::uint64_t count_in_windows();
// Allocations anywhere since start (shows that counting is live).
std::uint64_t count_total();
// True when malloc and its family are counted too (glibc, no AddressSanitizer).
bool counts_malloc();

}  // namespace carril::test::alloc
