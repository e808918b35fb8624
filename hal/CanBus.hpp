#pragma once
// A CAN controller port (classic CAN: 11/29-bit identifiers, up to 8 data bytes), the layer under
// bus-based device backends such as CANopen wheel drives. Every call is non-blocking and
// allocation-free, so a backend may use it from inside the control tick.
#include <cstdint>

namespace carril::hal {

constexpr std::uint32_t kCanStdIdMask = 0x7FFU;       // 11-bit identifier
constexpr std::uint32_t kCanExtIdMask = 0x1FFFFFFFU;  // 29-bit identifier
constexpr std::uint8_t kCanMaxLen = 8;                // classic CAN payload [bytes]

// Error classes carried in an error frame's id (the bits SocketCAN uses, CAN_ERR_*).
constexpr std::uint32_t kCanErrProtocol = 0x008U;  // protocol violation (bit, form, stuff error)
constexpr std::uint32_t kCanErrBusOff = 0x040U;    // the controller went bus-off

// One classic CAN frame.
struct CanFrame {
  std::uint32_t id = 0;   // identifier (11 or 29 bits); error frames: error class bits
  bool extended = false;  // 29-bit identifier
  bool rtr = false;       // remote request: no payload, len is the length asked for
  bool error = false;     // reported by a controller, not sent by a node (see kCanErr*)
  std::uint8_t len = 0;   // payload length [bytes], 0 to 8
  std::uint8_t data[kCanMaxLen] = {};
};

// Totals since the port was opened [frames or events]; they only grow.
struct CanBusCounters {
  std::uint64_t tx_frames = 0;     // transmitted on the bus
  std::uint64_t rx_frames = 0;     // handed out by receive(), error frames excluded
  std::uint64_t tx_dropped = 0;    // refused by send() (queue full, bus-off, invalid) or
                                   // discarded from the transmit queue at bus-off
  std::uint64_t rx_dropped = 0;    // lost because the receive queue was full (overrun)
  std::uint64_t error_frames = 0;  // error frames the controller reported
  std::uint64_t bus_off = 0;       // times the controller went bus-off
};

class CanBus {
 public:
  virtual ~CanBus() = default;
  // Queue a frame for transmission; false (counted in tx_dropped) when the transmit queue is
  // full, the controller is bus-off or the frame is invalid (len > 8, id too wide, error set).
  virtual bool send(const CanFrame& frame) = 0;
  // Take the oldest received frame (error frames included, error set); false when none waits.
  virtual bool receive(CanFrame& out) = 0;
  // The port's counters since it was opened.
  virtual CanBusCounters counters() const = 0;
  // Hands frames a batching transport holds to the wire (one system call for a period's
  // frames); a transport that sends at once has nothing to do. Non-blocking.
  virtual void flush() {}
};

}  // namespace carril::hal
