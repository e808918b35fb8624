#pragma once
// Where the firmware reports events (task overruns, state changes, faults): written inside the
// tick, drained outside it. Fixed capacity; a full log overwrites its oldest event (the newest
// say most about the present) and counts what it dropped, so a reader knows the history has gaps.
// Single-threaded: push and pop from the thread that owns it (one log per rate group thread).
#include <cstddef>
#include <cstdint>

#include "firmware/core/Event.hpp"
#include "firmware/core/RingBuffer.hpp"

namespace carril::fw {

// What a reporter (a TaskTable) holds, so it is not tied to one log capacity.
class EventSink {
 public:
  virtual ~EventSink() = default;
  // Records e; never blocks or allocates. Returns false when an older event was dropped for it.
  virtual bool push(const Event& e) = 0;
};

template <std::size_t N>
class EventLog final : public EventSink {
 public:
  // Appends e; when full, drops the oldest event (counted in dropped()) and returns false.
  bool push(const Event& e) override {
    if (ring_.push(e)) return true;
    ++dropped_;
    return false;
  }
  // Takes the oldest event into out; false when the log is empty.
  bool pop(Event& out) { return ring_.pop(out); }
  // Events held [events].
  std::size_t size() const { return ring_.size(); }
  static constexpr std::size_t capacity() { return N; }
  // Events overwritten before anyone popped them, since construction [events].
  std::uint64_t dropped() const { return dropped_; }

 private:
  RingBuffer<Event, N> ring_;
  std::uint64_t dropped_ = 0;
};

}  // namespace carril::fw
