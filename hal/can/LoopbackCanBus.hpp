#pragma once
// An in-process CAN bus for tests and the simulator: two or more endpoints on one virtual wire.
// A frame one endpoint sends reaches every other endpoint, and the sender itself only with own
// echo on, as on a real bus. Queues are sized at construction; nothing allocates afterwards.
// Not thread-safe: one thread sends, transfers and receives (lockstep).
#include <cstdint>
#include <limits>
#include <memory>

#include "hal/CanBus.hpp"

namespace carril::hal {

class LoopbackCanBus {
 public:
  struct Config {
    int endpoints = 2;      // nodes on the bus, at least 2
    int tx_depth = 32;      // transmit queue per endpoint [frames]
    int rx_depth = 64;      // receive queue per endpoint [frames]
    bool own_echo = false;  // senders also receive their own frames (SocketCAN RECV_OWN_MSGS)
  };
  static constexpr int kAll = std::numeric_limits<int>::max();

  explicit LoopbackCanBus(const Config& cfg);
  ~LoopbackCanBus();
  LoopbackCanBus(const LoopbackCanBus&) = delete;
  LoopbackCanBus& operator=(const LoopbackCanBus&) = delete;

  // The port of node i, 0 <= i < endpoints().
  CanBus& endpoint(int i);
  // Number of nodes on the bus.
  int endpoints() const { return cfg_.endpoints; }

  // Bus time passes: up to max_frames queued frames go on the wire, each to every receiver;
  // returns how many went [frames]. One node's frames go in send order (one FIFO, as SocketCAN
  // keeps them); between nodes arbitration decides: the lower identifier wins, a standard frame
  // beats an extended one with the same base identifier, a data frame beats a remote one.
  int transfer(int max_frames = kAll);

  // Fault injection. The next n frames on the wire are lost: each sender counts its frame
  // transmitted, nobody receives it.
  void drop_next(int n);
  // An error frame of class error_class (kCanErr*), reported by every node that is not bus-off.
  void inject_error_frame(std::uint32_t error_class = kCanErrProtocol);
  // Node i goes bus-off: its transmit queue is discarded (tx_dropped), an error frame of class
  // kCanErrBusOff tells it, and it sends and receives nothing until restart(i).
  void force_bus_off(int i);
  // Node i rejoins the bus (SocketCAN: `ip link set canX type can restart`).
  void restart(int i);
  // Whether node i is bus-off.
  bool bus_off(int i) const;
  // Frames lost on the wire to drop_next() so far.
  std::uint64_t frames_lost() const { return frames_lost_; }

 private:
  class Port;
  // A frame's arbitration field as sent on the wire (dominant 0 first): lower wins.
  static std::uint32_t arbitration_key(const CanFrame& f);
  void deliver(int sender, const CanFrame& f);

  Config cfg_;
  std::unique_ptr<Port[]> ports_;
  int drops_pending_ = 0;
  std::uint64_t frames_lost_ = 0;
};

}  // namespace carril::hal
