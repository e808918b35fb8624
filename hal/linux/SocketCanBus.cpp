#include "hal/linux/SocketCanBus.hpp"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <ctime>

namespace carril::hal {

static_assert(kCanErrBusOff == CAN_ERR_BUSOFF && kCanErrProtocol == CAN_ERR_PROT,
              "hal error classes must be SocketCAN's CAN_ERR_* bits");

// ---- CanTxBacklog ----

CanTxBacklog::CanTxBacklog(int capacity) : cap_(capacity < 1 ? 1 : capacity) {
  buf_ = std::make_unique<Entry[]>(std::size_t(cap_));
}

bool CanTxBacklog::push(const CanFrame& f, TimeNs t_ns) {
  if (full()) return false;
  buf_[std::size_t((head_ + size_) % cap_)] = Entry{f, t_ns};
  ++size_;
  return true;
}

int CanTxBacklog::expire(TimeNs now_ns, TimeNs deadline_ns) {
  int dropped = 0;
  // Frames are queued in time order, so the stale ones are at the front.
  while (size_ > 0 && now_ns - buf_[std::size_t(head_)].queued_ns > deadline_ns) {
    pop();
    ++dropped;
  }
  return dropped;
}

const CanFrame& CanTxBacklog::front() const {
  assert(size_ > 0);
  return buf_[std::size_t(head_)].frame;
}

void CanTxBacklog::pop() {
  if (size_ == 0) return;
  head_ = (head_ + 1) % cap_;
  --size_;
}

// ---- SocketCanBus ----

namespace {

bool valid(const CanFrame& f) {
  const std::uint32_t mask = f.extended ? kCanExtIdMask : kCanStdIdMask;
  return !f.error && f.len <= kCanMaxLen && (f.id & ~mask) == 0;
}

std::string quoted(const std::string& iface) {
  return "CAN interface '" + iface + "'";
}

// Checks, without SocketCAN, that iface exists, is up and is a CAN device; "" or the reason.
std::string check_interface(const std::string& iface) {
  if (iface.empty() || iface.size() >= IFNAMSIZ) {
    return quoted(iface) + ": the name must be 1 to " + std::to_string(IFNAMSIZ - 1) +
           " characters (can.interface in the controller config)";
  }
  int s = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (s < 0) s = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (s < 0) return quoted(iface) + ": cannot query interfaces: " + std::strerror(errno);
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, iface.c_str(), iface.size() + 1);
  std::string err;
  if (::ioctl(s, SIOCGIFFLAGS, &ifr) < 0) {
    err = errno == ENODEV ? quoted(iface) +
                                " not found: no such network interface (create it, e.g. `ip link "
                                "add dev vcan0 type vcan`, or fix can.interface in the config)"
                          : quoted(iface) + ": SIOCGIFFLAGS: " + std::strerror(errno);
  } else if ((ifr.ifr_flags & IFF_UP) == 0) {
    err = quoted(iface) + " is down: bring it up with `ip link set up " + iface + "`";
  } else if (::ioctl(s, SIOCGIFHWADDR, &ifr) == 0 && ifr.ifr_hwaddr.sa_family != ARPHRD_CAN) {
    err = quoted(iface) + " is not a CAN interface (link type " +
          std::to_string(ifr.ifr_hwaddr.sa_family) + ", expected " + std::to_string(ARPHRD_CAN) +
          ")";
  }
  ::close(s);
  return err;
}

}  // namespace

SocketCanBus::SocketCanBus(const Config& cfg) : cfg_(cfg), backlog_(cfg.tx_backlog) {
  if (cfg_.tx_batch > 1) {
    batch_ = std::make_unique<can_frame[]>(std::size_t(cfg_.tx_batch));
    batch_msgs_ = std::make_unique<mmsghdr[]>(std::size_t(cfg_.tx_batch));
    batch_iov_ = std::make_unique<iovec[]>(std::size_t(cfg_.tx_batch));
  }
  if (cfg_.rx_batch > 1) {
    const auto n = std::size_t(cfg_.rx_batch);
    rx_ = std::make_unique<can_frame[]>(n);
    rx_msgs_ = std::make_unique<mmsghdr[]>(n);
    rx_iov_ = std::make_unique<iovec[]>(n);
    // new[] of char is aligned for any fundamental type; kRxCtrl is a multiple of cmsghdr's.
    rx_ctrl_ = std::make_unique<char[]>(n * kRxCtrl);
    // The buffers never move: each message points at its own once, here. recvmmsg writes only
    // msg_len, msg_flags and msg_controllen, which receive() resets for the messages it filled.
    for (std::size_t k = 0; k < n; ++k) {
      rx_iov_[k] = iovec{&rx_[k], sizeof(can_frame)};
      rx_msgs_[k] = mmsghdr{};
      msghdr& h = rx_msgs_[k].msg_hdr;
      h.msg_iov = &rx_iov_[k];
      h.msg_iovlen = 1;
      h.msg_control = &rx_ctrl_[k * kRxCtrl];
      h.msg_controllen = kRxCtrl;
    }
  }
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) ::close(fd_);
}

SocketCanBus::OpenResult SocketCanBus::open(const Config& cfg) {
  OpenResult r;
  if (cfg.tx_backlog < 1 || cfg.send_deadline_ns <= 0 || cfg.tx_batch < 1 || cfg.tx_batch > 1024 ||
      cfg.rx_batch < 1 || cfg.rx_batch > 1024) {
    r.error = quoted(cfg.iface) +
              ": tx_backlog must be at least 1 frame, tx_batch and rx_batch 1 to 1024 and "
              "send_deadline_ns > 0";
    return r;
  }
  std::unique_ptr<SocketCanBus> bus(new SocketCanBus(cfg));
  r.error = bus->open_socket();
  if (r.error.empty()) r.bus = std::move(bus);
  return r;
}

std::string SocketCanBus::open_socket() {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  std::string err = check_interface(cfg_.iface);
  if (!err.empty()) return err;
  const int s = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (s < 0) {
    return quoted(cfg_.iface) + ": socket(PF_CAN, CAN_RAW): " + std::strerror(errno) +
           " (load the can and can-raw kernel modules)";
  }
  const can_err_mask_t err_mask = CAN_ERR_MASK;
  const int own = cfg_.receive_own ? 1 : 0;
  const int on = 1;
  const char* what = nullptr;
  if (::setsockopt(s, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) < 0) {
    what = "CAN_RAW_ERR_FILTER";
  } else if (::setsockopt(s, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &own, sizeof own) < 0) {
    what = "CAN_RAW_RECV_OWN_MSGS";
  } else if (::setsockopt(s, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) < 0) {
    what = "SO_RXQ_OVFL";
  }
  if (what == nullptr) {
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = int(::if_nametoindex(cfg_.iface.c_str()));
    if (addr.can_ifindex == 0 || ::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
      what = "bind";
    }
  }
  if (what != nullptr) {
    err = quoted(cfg_.iface) + ": " + what + ": " + std::strerror(errno);
    ::close(s);
    return err;
  }
  fd_ = s;
  last_ovfl_ = 0;
  rx_n_ = rx_next_ = 0;
  rx_drained_ = false;
  return {};
}

bool SocketCanBus::reopen() {
  counters_.tx_dropped += std::uint64_t(backlog_.size());
  backlog_.clear();
  error_ = open_socket();
  if (!error_.empty()) return false;
  link_down_ = false;
  return true;
}

TimeNs SocketCanBus::now() const {
  if (cfg_.now_ns != nullptr) return cfg_.now_ns();
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);  // vDSO: no system call
  return TimeNs(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void SocketCanBus::note_down() {
  if (!link_down_) ++link_down_events_;
  link_down_ = true;
}

SocketCanBus::Io SocketCanBus::write_frame(const CanFrame& f) {
  if (fd_ < 0) return Io::Failed;
  can_frame cf{};
  cf.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0U) | (f.rtr ? CAN_RTR_FLAG : 0U);
  cf.len = f.len;
  if (!f.rtr) std::memcpy(cf.data, f.data, f.len);
  const ssize_t n = ::send(fd_, &cf, sizeof cf, MSG_DONTWAIT);
  if (n == ssize_t(sizeof cf)) {
    ++counters_.tx_frames;
    link_down_ = false;
    return Io::Ok;
  }
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS)) return Io::Busy;
  if (n < 0 && (errno == ENETDOWN || errno == ENODEV || errno == ENXIO)) {
    note_down();
    return Io::Down;
  }
  return Io::Failed;
}

void SocketCanBus::flush_backlog() {
  counters_.tx_dropped += std::uint64_t(backlog_.expire(now(), cfg_.send_deadline_ns));
  while (!backlog_.empty()) {
    const Io io = write_frame(backlog_.front());
    if (io == Io::Busy) return;  // still full: try again on the next call
    if (io != Io::Ok) ++counters_.tx_dropped;
    backlog_.pop();
  }
}

bool SocketCanBus::send(const CanFrame& frame) {
  if (!valid(frame)) {
    ++counters_.tx_dropped;
    return false;
  }
  if (!backlog_.empty()) flush_backlog();
  if (batch_ && backlog_.empty()) {
    // Gathered for one system call; a full batch goes at once.
    can_frame& cf = batch_[std::size_t(batch_n_++)];
    cf = can_frame{};
    cf.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0U) | (frame.rtr ? CAN_RTR_FLAG : 0U);
    cf.len = frame.len;
    if (!frame.rtr) std::memcpy(cf.data, frame.data, frame.len);
    if (batch_n_ == cfg_.tx_batch) flush();
    return true;
  }
  if (backlog_.empty()) {
    switch (write_frame(frame)) {
      case Io::Ok:
        return true;
      case Io::Busy:
        break;  // hold it below
      case Io::Down:
      case Io::Failed:
        ++counters_.tx_dropped;
        return false;
    }
  }
  // Behind older held frames, or the kernel is full: hold it, keeping the send order.
  if (!backlog_.push(frame, now())) {
    ++counters_.tx_dropped;
    return false;
  }
  return true;
}

void SocketCanBus::flush() {
  if (batch_n_ == 0) return;
  const int n = batch_n_;
  batch_n_ = 0;
  int sent = 0;
  if (fd_ >= 0) {
    for (int i = 0; i < n; ++i) {
      batch_iov_[std::size_t(i)] = iovec{&batch_[std::size_t(i)], sizeof(can_frame)};
      batch_msgs_[std::size_t(i)] = mmsghdr{};
      batch_msgs_[std::size_t(i)].msg_hdr.msg_iov = &batch_iov_[std::size_t(i)];
      batch_msgs_[std::size_t(i)].msg_hdr.msg_iovlen = 1;
    }
    const int r = ::sendmmsg(fd_, batch_msgs_.get(), static_cast<unsigned>(n), MSG_DONTWAIT);
    if (r > 0) {
      sent = r;
      counters_.tx_frames += std::uint64_t(r);
      link_down_ = false;
    } else if (r < 0 && (errno == ENETDOWN || errno == ENODEV || errno == ENXIO)) {
      note_down();
      counters_.tx_dropped += std::uint64_t(n);
      return;
    }
  }
  // What the kernel had no room for waits in the backlog, in order, under the deadline.
  const TimeNs t = sent < n ? now() : 0;
  for (int i = sent; i < n; ++i) {
    const can_frame& cf = batch_[std::size_t(i)];
    CanFrame f;
    f.extended = (cf.can_id & CAN_EFF_FLAG) != 0;
    f.rtr = (cf.can_id & CAN_RTR_FLAG) != 0;
    f.id = cf.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.len = cf.len;
    std::memcpy(f.data, cf.data, sizeof f.data);
    if (fd_ < 0 || !backlog_.push(f, t)) ++counters_.tx_dropped;
  }
}

bool SocketCanBus::receive(CanFrame& out) {
  if (batch_n_ > 0) flush();  // a request waiting for its answer goes out first
  if (!backlog_.empty()) flush_backlog();
  if (fd_ < 0) return false;
  if (rx_) {
    // Two rounds at most: what the last batch left, then one new batch. A frame that is not a
    // classic one is skipped, as recvmsg's path refuses it.
    for (int round = 0; round < 2; ++round) {
      while (rx_next_ < rx_n_) {
        const int k = rx_next_++;
        mmsghdr& m = rx_msgs_[std::size_t(k)];
        if (decode(rx_[std::size_t(k)], m.msg_len, m.msg_hdr, out)) return true;
      }
      rx_n_ = rx_next_ = 0;
      if (rx_drained_ || round == 1) {
        rx_drained_ = false;  // the end of this drain; the next call asks the kernel
        return false;
      }
      const int cap = cfg_.rx_batch;
      for (int i = 0; i < rx_filled_; ++i) {
        mmsghdr& m = rx_msgs_[std::size_t(i)];
        m.msg_len = 0;
        m.msg_hdr.msg_flags = 0;
        m.msg_hdr.msg_controllen = kRxCtrl;
      }
      rx_filled_ = 0;
      ++receive_calls_;
      const int r =
          ::recvmmsg(fd_, rx_msgs_.get(), static_cast<unsigned>(cap), MSG_DONTWAIT, nullptr);
      if (r <= 0) {
        if (r < 0 && (errno == ENETDOWN || errno == ENODEV || errno == ENXIO)) note_down();
        return false;
      }
      rx_filled_ = r;
      rx_n_ = r;
      rx_drained_ = r < cap;
    }
    return false;
  }
  can_frame cf{};
  iovec iov{&cf, sizeof cf};
  alignas(cmsghdr) char ctrl[kRxCtrl];
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = ctrl;
  msg.msg_controllen = sizeof ctrl;
  ++receive_calls_;
  const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
  if (n < 0) {
    if (errno == ENETDOWN || errno == ENODEV || errno == ENXIO) note_down();
    return false;
  }
  return decode(cf, std::size_t(n), msg, out);
}

bool SocketCanBus::decode(const can_frame& cf, std::size_t len, msghdr& msg, CanFrame& out) {
  if (len != sizeof cf) return false;  // not a classic frame (CAN FD is off)
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
      std::uint32_t ovfl = 0;  // the socket's total of frames dropped for a full receive queue
      std::memcpy(&ovfl, CMSG_DATA(c), sizeof ovfl);
      counters_.rx_dropped += std::uint32_t(ovfl - last_ovfl_);
      last_ovfl_ = ovfl;
    }
  }
  link_down_ = false;
  CanFrame f;
  f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
  f.extended = !f.error && (cf.can_id & CAN_EFF_FLAG) != 0;
  f.rtr = !f.error && (cf.can_id & CAN_RTR_FLAG) != 0;
  f.id = cf.can_id & (f.error ? CAN_ERR_MASK : f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  f.len = cf.len > kCanMaxLen ? kCanMaxLen : cf.len;
  std::memcpy(f.data, cf.data, kCanMaxLen);
  if (f.rtr) std::memset(f.data, 0, kCanMaxLen);
  if (f.error) {
    ++counters_.error_frames;
    if ((f.id & CAN_ERR_BUSOFF) != 0) ++counters_.bus_off;
  } else {
    ++counters_.rx_frames;
  }
  out = f;
  return true;
}

}  // namespace carril::hal
