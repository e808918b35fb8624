#include "hal/canopen/Heartbeat.hpp"

#include "hal/canopen/Frames.hpp"

namespace carril::hal::canopen {

bool HeartbeatMonitor::watch(std::uint8_t node, TimeNs timeout_ns) {
  if (count_ >= kMaxNodes || node < 1 || node > kMaxNodeId || timeout_ns <= 0 ||
      find(node) != nullptr) {
    return false;
  }
  Node& n = nodes_[count_++];
  n = Node{};
  n.id = node;
  n.timeout_ns = timeout_ns;
  return true;
}

const HeartbeatMonitor::Node* HeartbeatMonitor::find(std::uint8_t node) const {
  for (std::size_t i = 0; i < count_; ++i) {
    if (nodes_[i].id == node) return &nodes_[i];
  }
  return nullptr;
}

bool HeartbeatMonitor::on_frame(const CanFrame& f, TimeNs now_ns) {
  std::uint8_t id = 0, state = 0;
  if (!decode_heartbeat(f, id, state)) return false;
  for (std::size_t i = 0; i < count_; ++i) {
    Node& n = nodes_[i];
    if (n.id != id) continue;
    if (state == static_cast<std::uint8_t>(NmtState::BootUp)) ++n.boot_ups;
    n.heard = true;
    n.state = state;
    n.last_ns = now_ns;
    n.lost = false;
    return true;
  }
  ++unknown_;
  return false;
}

std::size_t HeartbeatMonitor::poll(TimeNs now_ns) {
  std::size_t lost = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    Node& n = nodes_[i];
    if (n.heard && !n.lost && now_ns - n.last_ns > n.timeout_ns) {
      n.lost = true;
      ++n.losses;
    }
    if (n.lost) ++lost;
  }
  return lost;
}

}  // namespace carril::hal::canopen
