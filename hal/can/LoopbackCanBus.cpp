#include "hal/can/LoopbackCanBus.hpp"

#include <cassert>

namespace carril::hal {

namespace {

// A fixed-capacity FIFO of frames; the storage is taken once, at construction of the bus.
class FrameQueue {
 public:
  void allocate(int capacity) {
    buf_ = std::make_unique<CanFrame[]>(std::size_t(capacity));
    cap_ = capacity;
  }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == cap_; }
  int size() const { return size_; }
  const CanFrame& front() const { return buf_[std::size_t(head_)]; }
  bool push(const CanFrame& f) {
    if (full()) return false;
    buf_[std::size_t((head_ + size_) % cap_)] = f;
    ++size_;
    return true;
  }
  bool pop(CanFrame& out) {
    if (empty()) return false;
    out = buf_[std::size_t(head_)];
    head_ = (head_ + 1) % cap_;
    --size_;
    return true;
  }
  void clear() { head_ = size_ = 0; }

 private:
  std::unique_ptr<CanFrame[]> buf_;
  int cap_ = 0, head_ = 0, size_ = 0;
};

bool valid(const CanFrame& f) {
  const std::uint32_t mask = f.extended ? kCanExtIdMask : kCanStdIdMask;
  return !f.error && f.len <= kCanMaxLen && (f.id & ~mask) == 0;
}

}  // namespace

class LoopbackCanBus::Port final : public CanBus {
 public:
  bool send(const CanFrame& frame) override {
    if (bus_off_ || !valid(frame) || !tx_.push(frame)) {
      ++counters_.tx_dropped;
      return false;
    }
    return true;
  }
  bool receive(CanFrame& out) override {
    if (!rx_.pop(out)) return false;
    if (!out.error) ++counters_.rx_frames;  // error frames were counted when reported
    return true;
  }
  CanBusCounters counters() const override { return counters_; }

  // Bus side.
  void arrive(const CanFrame& f) {
    if (f.error) ++counters_.error_frames;
    if (!rx_.push(f)) ++counters_.rx_dropped;
  }

  FrameQueue tx_, rx_;
  CanBusCounters counters_{};
  bool bus_off_ = false;
};

LoopbackCanBus::LoopbackCanBus(const Config& cfg) : cfg_(cfg) {
  assert(cfg.endpoints >= 2 && cfg.tx_depth >= 1 && cfg.rx_depth >= 1);
  ports_ = std::make_unique<Port[]>(std::size_t(cfg.endpoints));
  for (int i = 0; i < cfg.endpoints; ++i) {
    ports_[std::size_t(i)].tx_.allocate(cfg.tx_depth);
    ports_[std::size_t(i)].rx_.allocate(cfg.rx_depth);
  }
}

LoopbackCanBus::~LoopbackCanBus() = default;

CanBus& LoopbackCanBus::endpoint(int i) {
  assert(i >= 0 && i < cfg_.endpoints);
  return ports_[std::size_t(i)];
}

std::uint32_t LoopbackCanBus::arbitration_key(const CanFrame& f) {
  // The bits in wire order, 32 in all: base id (11), RTR or SRR (1), IDE (1), extended id (18),
  // RTR (1). SRR and IDE are recessive (1), so a standard frame beats an extended one with the
  // same base id.
  if (!f.extended) return (f.id & kCanStdIdMask) << 21 | std::uint32_t(f.rtr) << 20;
  const std::uint32_t base = (f.id >> 18) & kCanStdIdMask;
  const std::uint32_t low = f.id & 0x3FFFFU;
  return base << 21 | 1U << 20 | 1U << 19 | low << 1 | std::uint32_t(f.rtr);
}

int LoopbackCanBus::transfer(int max_frames) {
  int sent = 0;
  while (sent < max_frames) {
    int winner = -1;
    std::uint32_t best = 0;
    for (int i = 0; i < cfg_.endpoints; ++i) {
      const Port& p = ports_[std::size_t(i)];
      if (p.tx_.empty()) continue;
      const std::uint32_t key = arbitration_key(p.tx_.front());
      if (winner < 0 || key < best) {  // a tie (one id on two nodes, illegal): lower node
        winner = i;
        best = key;
      }
    }
    if (winner < 0) break;
    Port& w = ports_[std::size_t(winner)];
    CanFrame f;
    w.tx_.pop(f);
    ++w.counters_.tx_frames;
    ++sent;
    if (drops_pending_ > 0) {
      --drops_pending_;
      ++frames_lost_;
      continue;
    }
    deliver(winner, f);
  }
  return sent;
}

void LoopbackCanBus::deliver(int sender, const CanFrame& f) {
  for (int i = 0; i < cfg_.endpoints; ++i) {
    Port& p = ports_[std::size_t(i)];
    if ((i == sender && !cfg_.own_echo) || p.bus_off_) continue;
    p.arrive(f);
  }
}

void LoopbackCanBus::drop_next(int n) {
  if (n > 0) drops_pending_ += n;
}

void LoopbackCanBus::inject_error_frame(std::uint32_t error_class) {
  CanFrame e;
  e.error = true;
  e.id = error_class;
  e.len = kCanMaxLen;  // SocketCAN error frames carry 8 bytes of detail, zero here
  for (int i = 0; i < cfg_.endpoints; ++i) {
    Port& p = ports_[std::size_t(i)];
    if (!p.bus_off_) p.arrive(e);
  }
}

void LoopbackCanBus::force_bus_off(int i) {
  Port& p = ports_[std::size_t(i)];
  if (p.bus_off_) return;  // already off: no new event
  p.bus_off_ = true;
  ++p.counters_.bus_off;
  p.counters_.tx_dropped += std::uint64_t(p.tx_.size());
  p.tx_.clear();
  CanFrame e;
  e.error = true;
  e.id = kCanErrBusOff;
  e.len = kCanMaxLen;
  p.arrive(e);
}

void LoopbackCanBus::restart(int i) {
  ports_[std::size_t(i)].bus_off_ = false;
}

bool LoopbackCanBus::bus_off(int i) const {
  return ports_[std::size_t(i)].bus_off_;
}

}  // namespace carril::hal
