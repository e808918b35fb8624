#pragma once
// Heartbeat consumer (CiA 301, 7.2.8.3.2.2) for the drives a master watches: each node's NMT
// state as its heartbeat reports it, boot-ups (a node that restarted), and a node whose heartbeat
// stopped for longer than its consumer time, latched until the node is heard again. Fixed
// capacity, no heap; fed frames and the loop time by the caller.
#include <cstddef>
#include <cstdint>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"

namespace carril::hal::canopen {

class HeartbeatMonitor {
 public:
  static constexpr std::size_t kMaxNodes = 8;

  struct Node {
    std::uint8_t id = 0;
    TimeNs timeout_ns = 0;       // consumer time [ns]
    bool heard = false;          // a heartbeat or boot-up came at least once
    std::uint8_t state = 0;      // last NMT state reported (nmt_state_name())
    TimeNs last_ns = 0;          // when [ns]
    bool lost = false;           // heard, then silent for longer than timeout_ns
    std::uint32_t boot_ups = 0;  // boot-up messages (the node restarted)
    std::uint32_t losses = 0;    // times it was lost
  };

  // Init only: watch `node` (1 to 127) with consumer time `timeout_ns` [ns]. False when full,
  // the id is invalid or already watched.
  bool watch(std::uint8_t node, TimeNs timeout_ns);
  // A received frame at loop time `now_ns`: true when it was a watched node's heartbeat. Other
  // heartbeats (unknown nodes) are counted in unknown().
  bool on_frame(const CanFrame& f, TimeNs now_ns);
  // Marks nodes silent for longer than their consumer time as lost; returns how many are lost.
  std::size_t poll(TimeNs now_ns);

  std::size_t size() const { return count_; }
  const Node& node(std::size_t i) const { return nodes_[i]; }
  // The watched node with id `node`, or nullptr.
  const Node* find(std::uint8_t node) const;
  std::uint64_t unknown() const { return unknown_; }

 private:
  Node nodes_[kMaxNodes];
  std::size_t count_ = 0;
  std::uint64_t unknown_ = 0;
};

}  // namespace carril::hal::canopen
