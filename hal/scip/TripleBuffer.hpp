#pragma once
// Lock-free single-writer, single-reader triple buffer: the writer fills back() and publish()es
// it; the reader take()s the newest published value without waiting and keeps it (front())
// until its next take(). Neither side ever blocks or copies; three values are allocated once, at
// construction. Used between a device thread and the control tick.
#include <atomic>
#include <cstdint>
#include <memory>

namespace carril::hal {

template <class T>
class TripleBuffer {
 public:
  TripleBuffer() : slots_(std::make_unique<T[]>(3)) {}
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  // Writer: the value to fill next (owned by the writer until publish()).
  T& back() { return slots_[back_]; }
  // Writer: hands back() to the reader; an older value the reader has not taken is recycled.
  void publish() { back_ = ready_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex; }

  // Reader: true when a value newer than front() was published and is now front().
  bool take() {
    if ((ready_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    front_ = ready_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  // Reader: the value taken last (a default T before the first take()).
  const T& front() const { return slots_[front_]; }

 private:
  static constexpr std::uint32_t kIndex = 3U;  // low bits: slot index
  static constexpr std::uint32_t kFresh = 4U;  // set by publish(), cleared by take()
  std::unique_ptr<T[]> slots_;
  std::uint32_t front_ = 0;  // reader's
  std::uint32_t back_ = 2;   // writer's
  std::atomic<std::uint32_t> ready_{1};
};

}  // namespace carril::hal
