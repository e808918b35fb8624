#pragma once
// Hands the newest value from one writer thread to one reader thread, neither ever waiting (the
// wait-free form of a double buffer). Three slots: the writer fills its back slot and swaps it
// with the shared middle slot in one atomic exchange; the reader swaps the middle slot for its
// front slot only when the writer marked it fresh. Each slot is owned by exactly one side at a
// time, so the reader never sees a half-written value. Values the reader did not fetch in time
// are replaced by newer ones (latest wins), which is what a slow rate group handing results to
// the tick wants. Each published value carries a sequence number (1, 2, ...), so the reader
// knows whether it is new and how many it missed. The one triple buffer: the device threads
// (the SCIP lidar's reader) and the firmware's rate groups both use it. The slots live inside the
// object: allocate a buffer of large values (a scan) with its owner, at init.
#include <atomic>
#include <cstdint>

namespace carril::hal {

template <typename T>
class TripleBuffer {
  static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

 public:
  // --- writer thread only ---

  // The slot to fill; stays the writer's until publish().
  T& write_slot() { return slots_[back_].value; }
  // Makes the filled slot the newest value and takes another to fill next. Never waits.
  void publish() {
    slots_[back_].seq = ++published_;
    // release: the slot's contents are visible before the reader can take it; acquire: the
    // slot handed back was released by the reader, which has finished reading it.
    back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex;
  }
  // write_slot() = v, then publish().
  void write(const T& v) {
    write_slot() = v;
    publish();
  }

  // --- reader thread only ---

  // Takes the newest published value if there is one the reader has not taken yet; true then.
  // Never waits.
  bool fetch() {
    // Only the writer sets kFresh and only this thread clears it, so fresh stays fresh until
    // the exchange below; exchanging when not fresh would take back an older value.
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  // The value fetch() last took (a default-constructed T before the first).
  const T& value() const { return slots_[front_].value; }
  // Its sequence number: 0 before the first fetch, then 1 for the first value published, ...
  std::uint64_t seq() const { return slots_[front_].seq; }

 private:
  static constexpr std::uint32_t kIndex = 3;  // slot index bits of middle_
  static constexpr std::uint32_t kFresh = 4;  // middle_ holds a value the reader has not taken

  // A cache line each, so the two threads do not slow each other down through false sharing.
  struct alignas(64) Slot {
    T value{};
    std::uint64_t seq = 0;
  };
  Slot slots_[3];
  alignas(64) std::atomic<std::uint32_t> middle_{1};
  alignas(64) std::uint32_t back_ = 2;   // writer's
  std::uint64_t published_ = 0;          // writer's
  alignas(64) std::uint32_t front_ = 0;  // reader's
};

}  // namespace carril::hal
