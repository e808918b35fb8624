#pragma once
// CanBus over a Linux SocketCAN raw socket (can0, vcan0, ...). open() runs at init and may use
// the OS and the heap; afterwards send() and receive() are non-blocking (MSG_DONTWAIT), one
// frame per call, allocation-free, so the control tick may call them (it bounds its reads).
// When the kernel's queue is full (EAGAIN, ENOBUFS) a frame waits in a small fixed backlog and
// is retried on the next send() or receive(); a frame older than the send deadline is dropped
// (tx_dropped), since a late setpoint is worse than none. Error frames are enabled and come out
// of receive() with error set and the CAN_ERR_* class bits in id (the same bits as kCanErr*).
#include <cstdint>
#include <memory>
#include <string>

#include <linux/can.h>
#include <sys/socket.h>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"

namespace carril::hal {

// A fixed ring of frames waiting for the kernel, each with the time it was queued; pure (no OS
// calls), so its deadline logic is tested without a socket.
class CanTxBacklog {
 public:
  // capacity [frames], at least 1; the storage is taken here, once.
  explicit CanTxBacklog(int capacity);
  // Appends a frame queued at t_ns [ns]; false when full.
  bool push(const CanFrame& f, TimeNs t_ns);
  // Drops from the front every frame queued more than deadline_ns [ns] before now_ns; returns
  // how many [frames].
  int expire(TimeNs now_ns, TimeNs deadline_ns);
  // The oldest waiting frame; only when !empty().
  const CanFrame& front() const;
  void pop();
  void clear() { head_ = size_ = 0; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == cap_; }
  int size() const { return size_; }

 private:
  struct Entry {
    CanFrame frame;
    TimeNs queued_ns;
  };
  std::unique_ptr<Entry[]> buf_;
  int cap_ = 0, head_ = 0, size_ = 0;
};

class SocketCanBus final : public CanBus {
 public:
  struct Config {
    std::string iface = "can0";            // interface name (controller config: can.interface)
    int tx_backlog = 16;                   // frames held while the kernel queue is full
    TimeNs send_deadline_ns = 10'000'000;  // a held frame older than this is dropped [ns]
    bool receive_own = false;              // also receive our own frames (CAN_RAW_RECV_OWN_MSGS)
    int tx_batch = 1;  // frames send() gathers for one sendmmsg at flush() (or when full, or at
                       // the next receive()); 1: each frame is sent at once
    int rx_batch = 1;  // frames one recvmmsg takes from the kernel for the receive() calls that
                       // follow; 1: one recvmsg per receive()
    TimeNs (*now_ns)() = nullptr;  // time for the deadline [ns]; null: CLOCK_MONOTONIC
  };
  // What open() gives: a bus, or a message naming the interface and what is wrong with it.
  struct OpenResult {
    std::unique_ptr<SocketCanBus> bus;
    std::string error;  // "" when bus is set
  };

  // Opens a raw socket bound to cfg.iface. Fails, with a message naming the interface, when the
  // name is invalid, the interface does not exist, is down, is not a CAN interface, or the kernel
  // has no SocketCAN. Init only: uses the OS and the heap.
  static OpenResult open(const Config& cfg);

  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  bool send(const CanFrame& frame) override;
  // rx_dropped (the socket's receive queue overran) is learned with the next frame received.
  // With rx_batch > 1 the frames come from one recvmmsg; after a batch that emptied the kernel's
  // queue, the next call returns false without a system call (the end of the caller's drain)
  // and the one after asks the kernel again.
  bool receive(CanFrame& out) override;
  // recvmsg and recvmmsg calls made so far [calls]: each is a system call (a costly trap under
  // user-mode-linux: about 75 us).
  std::uint64_t receive_calls() const { return receive_calls_; }
  // Sends the gathered frames (tx_batch > 1) with one sendmmsg; what the kernel has no room for
  // waits in the backlog.
  void flush() override;
  CanBusCounters counters() const override { return counters_; }

  // The interface went down or away (ENETDOWN, ENODEV) at the last send or receive; cleared by
  // the next frame that goes through or by reopen().
  bool link_down() const { return link_down_; }
  // Times a send or receive found the interface down [events].
  std::uint64_t link_down_events() const { return link_down_events_; }
  // Frames waiting in the backlog for the kernel [frames].
  int backlog() const { return backlog_.size(); }
  // Closes and opens the socket again (after the interface came back up); the backlog is
  // discarded (tx_dropped). Init-level: not for the tick. False, with the reason in error().
  bool reopen();
  // Why the last reopen() failed; "" otherwise.
  const std::string& error() const { return error_; }
  // The raw socket's descriptor (tests, poll()).
  int fd() const { return fd_; }
  const Config& config() const { return cfg_; }

 private:
  enum class Io : std::uint8_t { Ok, Busy, Down, Failed };
  explicit SocketCanBus(const Config& cfg);
  // Opens the socket into fd_; "" or the reason.
  std::string open_socket();
  Io write_frame(const CanFrame& f);
  // One received classic frame (with its control data) into out and the counters; false when it
  // is not a classic frame.
  bool decode(const can_frame& cf, std::size_t len, msghdr& msg, CanFrame& out);
  // Sends held frames while the kernel takes them; drops those past the deadline.
  void flush_backlog();
  TimeNs now() const;
  void note_down();

  Config cfg_;
  int fd_ = -1;
  CanTxBacklog backlog_;
  std::unique_ptr<can_frame[]> batch_;  // tx_batch frames, taken at open
  std::unique_ptr<mmsghdr[]> batch_msgs_;
  std::unique_ptr<iovec[]> batch_iov_;
  int batch_n_ = 0;
  // rx_batch > 1: the frames of the last recvmmsg, taken at open; rx_next_ of rx_n_ handed out.
  static constexpr std::size_t kRxCtrl = CMSG_SPACE(sizeof(std::uint32_t));
  std::unique_ptr<can_frame[]> rx_;
  std::unique_ptr<mmsghdr[]> rx_msgs_;
  std::unique_ptr<iovec[]> rx_iov_;
  std::unique_ptr<char[]> rx_ctrl_;  // rx_batch control buffers of kRxCtrl bytes, aligned
  int rx_n_ = 0, rx_next_ = 0;
  int rx_filled_ =
      0;  // messages the last recvmmsg wrote into (their lengths reset before the next)
  bool rx_drained_ = false;  // the last batch emptied the kernel's queue
  std::uint64_t receive_calls_ = 0;
  CanBusCounters counters_{};
  bool link_down_ = false;
  std::uint64_t link_down_events_ = 0;
  std::uint32_t last_ovfl_ = 0;  // the kernel's SO_RXQ_OVFL total seen last
  std::string error_;
};

}  // namespace carril::hal
