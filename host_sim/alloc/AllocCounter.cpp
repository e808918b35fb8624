#include "host_sim/alloc/AllocCounter.hpp"

#include <cstdlib>
#include <new>

// glibc exports its allocator under __libc_* names, so malloc can be wrapped without dlsym.
// AddressSanitizer owns malloc: there only operator new is counted.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define CARRIL_COUNT_MALLOC 1
#else
#define CARRIL_COUNT_MALLOC 0
#endif

namespace {
// Plain globals: the firmware's tick runs on one thread and a window is opened around it.
bool g_in_window = false;
std::uint64_t g_in_windows = 0;
std::uint64_t g_total = 0;

inline void note() {
  ++g_total;
  if (g_in_window) ++g_in_windows;
}
}  // namespace

namespace carril::alloc {
void begin_window() {
  g_in_window = true;
}
void end_window() {
  g_in_window = false;
}
std::uint64_t count_in_windows() {
  return g_in_windows;
}
std::uint64_t count_total() {
  return g_total;
}
bool counts_malloc() {
  return CARRIL_COUNT_MALLOC != 0;
}
}  // namespace carril::alloc

#if CARRIL_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) {
  note();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t s) {
  note();
  return __libc_calloc(n, s);
}
void* realloc(void* p, std::size_t n) {
  note();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t a, std::size_t n) {
  note();
  return __libc_memalign(a, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  note();
  return __libc_memalign(a, n);
}
void* valloc(std::size_t n) {
  note();
  return __libc_valloc(n);
}
void* pvalloc(std::size_t n) {
  note();
  return __libc_pvalloc(n);
}
int posix_memalign(void** out, std::size_t a, std::size_t n) {
  note();
  void* p = __libc_memalign(a, n);
  if (p == nullptr) return 12;  // ENOMEM
  *out = p;
  return 0;
}
void free(void* p) {
  __libc_free(p);
}
}
#define CARRIL_RAW_ALLOC(n) __libc_malloc(n)
#define CARRIL_RAW_ALIGNED(a, n) __libc_memalign(a, n)
#define CARRIL_RAW_FREE(p) __libc_free(p)
#else
#define CARRIL_RAW_ALLOC(n) std::malloc(n)
#define CARRIL_RAW_ALIGNED(a, n) std::aligned_alloc(a, ((n) + (a)-1) / (a) * (a))
#define CARRIL_RAW_FREE(p) std::free(p)
#endif

// operator new counts once, then takes raw memory (not through the counting malloc).
void* operator new(std::size_t n) {
  note();
  if (void* p = CARRIL_RAW_ALLOC(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  note();
  return CARRIL_RAW_ALLOC(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept {
  return operator new(n, t);
}
void* operator new(std::size_t n, std::align_val_t a) {
  note();
  if (void* p = CARRIL_RAW_ALIGNED(std::size_t(a), n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return operator new(n, a);
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  note();
  return CARRIL_RAW_ALIGNED(std::size_t(a), n ? n : 1);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t& t) noexcept {
  return operator new(n, a, t);
}
void operator delete(void* p) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete[](void* p) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete(void* p, std::size_t) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  CARRIL_RAW_FREE(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  CARRIL_RAW_FREE(p);
}
