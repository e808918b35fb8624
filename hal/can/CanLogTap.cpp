#include "hal/can/CanLogTap.hpp"

#include <cstring>

namespace carril::hal {

CanLogTap::CanLogTap(CanBus& inner, int capacity, const char* iface, NowFn now, void* now_ctx)
    : inner_(inner),
      cap_(std::uint64_t(capacity < 1 ? 1 : capacity)),
      now_(now),
      now_ctx_(now_ctx) {
  ring_ = std::make_unique<Record[]>(cap_);
  if (iface != nullptr) std::strncpy(iface_, iface, sizeof iface_ - 1);
}

bool CanLogTap::send(const CanFrame& frame) {
  if (!inner_.send(frame)) return false;
  record(frame, true);
  return true;
}

bool CanLogTap::receive(CanFrame& out) {
  if (!inner_.receive(out)) return false;
  record(out, false);
  return true;
}

void CanLogTap::record(const CanFrame& f, bool tx) {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  // acquire: the consumer is done reading the slot it released.
  if (head - tail_.load(std::memory_order_acquire) >= cap_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  Record& r = ring_[head % cap_];
  r.frame = f;
  r.t_ns = now_ != nullptr ? now_(now_ctx_) : 0;
  r.tx = tx;
  head_.store(head + 1, std::memory_order_release);  // publishes the record
}

bool CanLogTap::pop(Record& out) {
  const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  if (tail == head_.load(std::memory_order_acquire)) return false;
  out = ring_[tail % cap_];
  tail_.store(tail + 1, std::memory_order_release);  // hands the slot back
  return true;
}

std::size_t CanLogTap::pending() const {
  return std::size_t(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire));
}

}  // namespace carril::hal
