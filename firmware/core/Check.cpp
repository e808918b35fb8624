#include "firmware/core/Check.hpp"

#include <atomic>

namespace carril::fw {

namespace {
std::atomic<std::uint32_t> g_count{0};
std::atomic<const char*> g_file{nullptr};
std::atomic<int> g_line{0};
}  // namespace

bool check_failed(const char* file, int line) {
  // The first failure's place is written before the count that announces it is incremented.
  if (g_count.load(std::memory_order_relaxed) == 0) {
    const char* none = nullptr;
    if (g_file.compare_exchange_strong(none, file, std::memory_order_relaxed)) {
      g_line.store(line, std::memory_order_relaxed);
    }
  }
  g_count.fetch_add(1, std::memory_order_release);
  return false;
}

CheckFailures check_failures() {
  CheckFailures f;
  f.count = g_count.load(std::memory_order_acquire);
  f.file = g_file.load(std::memory_order_relaxed);
  f.line = g_line.load(std::memory_order_relaxed);
  return f;
}

}  // namespace carril::fw
