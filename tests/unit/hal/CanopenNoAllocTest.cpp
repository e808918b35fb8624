// CanopenWheelDrives' control-tick calls (read, set_velocity, requests, sync) never allocate,
// faults and recoveries included. The global operator new of this test binary counts the
// allocations made while a window is open (the hal tests do not link host_sim's counter, which
// the cross build does not have).
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>

#include "CanopenTestBench.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"

namespace {
bool g_window = false;
std::uint64_t g_allocs = 0;

void* counted(std::size_t n) {
  if (g_window) ++g_allocs;
  void* p = std::malloc(n == 0 ? 1 : n);
  if (p == nullptr) std::abort();  // a test binary out of memory: nothing to recover
  return p;
}
}  // namespace

void* operator new(std::size_t n) {
  return counted(n);
}
void* operator new[](std::size_t n) {
  return counted(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_window) ++g_allocs;
  return std::malloc(n == 0 ? 1 : n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  if (g_window) ++g_allocs;
  return std::malloc(n == 0 ? 1 : n);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace carril::hal::canopen::test {
namespace {

TEST(CanopenNoAlloc, TheCounterCounts) {
  g_window = true;
  const std::uint64_t before = g_allocs;
  auto* v = new std::vector<int>(100);
  g_window = false;
  delete v;
  EXPECT_GE(g_allocs - before, 1U);
}

TEST(CanopenNoAlloc, ControlTicksNeverAllocateThroughFaultsAndRecoveries) {
  Bench b;
  ASSERT_TRUE(b.drives().init().ok);
  const std::uint64_t before = g_allocs;
  WheelFeedbackSet fb;
  float sp[2] = {1.0F, -1.0F};
  for (int k = 0; k < 600; ++k) {
    b.clock().t += 10 * kMs;
    b.pump();  // the slaves and the bus may allocate (test code); only the master is counted
    if (k == 100) b.slaves().fault(b.slave(2), 0x2310);  // EMCY
    if (k == 200) b.slave(3).dead = true;                // heartbeat lost
    if (k == 250) b.slave(3).dead = false;
    if (k == 350) b.bus().force_bus_off(0);  // bus-off
    if (k == 400) b.bus().restart(0);
    g_window = true;
    b.drives().read(fb);
    if (k == 0 || k == 150 || k == 300 || k == 500) {
      b.drives().reset_faults();
      b.drives().enable();
    }
    if (k == 550) b.drives().quick_stop();
    sp[0] = float(k % 7);
    b.drives().set_velocity(sp, 2);
    b.drives().sync();
    g_window = false;
    b.pump();
  }
  EXPECT_EQ(g_allocs - before, 0U);
  // The run went through what it meant to: faults latched, resets sent, running in between.
  EXPECT_GE(b.drives().counters().faults, 3U);
  EXPECT_GE(b.drives().counters().fault_resets, 1U);
  EXPECT_EQ(b.drives().counters().bus_offs, 1U);
  // Drive 3 silent, then both drives unheard during the bus-off.
  EXPECT_EQ(b.drives().counters().heartbeat_losses, 3U);
}

}  // namespace
}  // namespace carril::hal::canopen::test
