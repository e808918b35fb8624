#pragma once
// Programming errors: CARRIL_CHECK(cond) is an always-on check (F Prime's FW_ASSERT; assert()
// vanishes in Release, which is what the robot runs). A failed check is counted and its first
// place kept; the Controller sees the count change at its next tick, latches Fault::CheckFailed
// (a safe stop, logged with the check's line) and the caller takes the safe way out it names
// (a container refuses the write, an index is clamped). The expression's value is cond, so a
// caller writes `if (!CARRIL_CHECK(i < n)) return;`. Hardware and input errors are faults or
// Status, not checks: a check that fails is a bug in carril.
#include <cstdint>

namespace carril::fw {

// Counts a failed check made at file:line; returns false (the check's value). Never returns
// early, never allocates, never blocks: callable from any thread, inside a tick.
[[gnu::cold, gnu::noinline]] bool check_failed(const char* file, int line);

// What failed so far, in this process (every firmware instance in it shares the count: a
// programming error anywhere stops them all).
struct CheckFailures {
  std::uint32_t count = 0;     // checks failed since the process started
  const char* file = nullptr;  // the first failure's source file (a static string)
  int line = 0;                // ... and line
};
CheckFailures check_failures();

}  // namespace carril::fw

#define CARRIL_CHECK(cond)                             \
  (__builtin_expect(static_cast<bool>(cond), 1) ? true \
                                                : ::carril::fw::check_failed(__FILE__, __LINE__))
