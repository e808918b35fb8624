#pragma once
// A CanBus decorator that records every frame sent and received through it, for `--can-log`.
// send() and receive() only copy the frame and a timestamp into a fixed lock-free
// single-producer single-consumer ring: no formatting, no I/O, no lock, no heap, so the tick may
// use it. drain(), outside the tick (a slow thread, or after the run), formats the records as
// can-utils' candump log lines (hal/can/Candump), which canplayer and log2asc read. When the
// ring is full a record is dropped and counted, never waited for.
// Threads: one thread calls send/receive (the producer), one calls drain (the consumer).
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"
#include "hal/can/Candump.hpp"

namespace carril::hal {

class CanLogTap final : public CanBus {
 public:
  // One recorded frame.
  struct Record {
    CanFrame frame;
    TimeNs t_ns = 0;  // from the time source [ns since the epoch for candump]
    bool tx = false;  // sent through the tap (false: received)
  };
  // The time source: called once per recorded frame, on the producer's thread [ns].
  using NowFn = TimeNs (*)(void* ctx);

  // Wraps `inner` (not owned; outlives the tap). capacity [records], at least 1, taken here;
  // iface: the interface name written in each line (up to 15 characters, longer is cut).
  CanLogTap(CanBus& inner, int capacity, const char* iface, NowFn now, void* now_ctx);

  // Sends through the inner bus; a frame it accepted is recorded.
  bool send(const CanFrame& frame) override;
  // Receives from the inner bus; a frame it gave is recorded (error frames too).
  bool receive(CanFrame& out) override;
  // The inner bus's counters.
  CanBusCounters counters() const override { return inner_.counters(); }
  // The inner bus's batched frames go to the wire.
  void flush() override { inner_.flush(); }

  // Consumer: takes the oldest record; false when none waits.
  bool pop(Record& out);
  // Consumer: formats up to max_lines waiting records as candump lines, each ending in '\n',
  // and calls write(line, length) for each; returns how many [lines].
  template <typename Write>
  std::size_t drain(Write&& write, std::size_t max_lines = SIZE_MAX) {
    char line[kCandumpMaxLine + 2];
    Record r;
    std::size_t n = 0;
    while (n < max_lines && pop(r)) {
      std::size_t len = format_candump(r.frame, r.t_ns, iface_, line, sizeof line - 1);
      line[len++] = '\n';
      write(static_cast<const char*>(line), len);
      ++n;
    }
    return n;
  }

  // Records lost because the ring was full [records].
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  // Records written into the ring so far [records].
  std::uint64_t recorded() const { return head_.load(std::memory_order_relaxed); }
  // Records waiting for drain() [records].
  std::size_t pending() const;
  const char* iface() const { return iface_; }

 private:
  void record(const CanFrame& f, bool tx);

  CanBus& inner_;
  std::unique_ptr<Record[]> ring_;
  std::uint64_t cap_;
  char iface_[16] = {};
  NowFn now_;
  void* now_ctx_;
  // head_: written by the producer only; tail_: by the consumer only. Apart, on their own cache
  // lines, so the two threads do not share one.
  alignas(64) std::atomic<std::uint64_t> head_{0};
  alignas(64) std::atomic<std::uint64_t> tail_{0};
  alignas(64) std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace carril::hal
