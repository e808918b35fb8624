// SocketCanBus. The pure tests (backlog, open() refusing a missing or non-CAN interface) run
// everywhere; the vcan0 tests need a kernel with SocketCAN and a vcan0 that is up, and skip
// with the reason otherwise. CTest hil_socketcan runs this binary inside user-mode-linux, where
// tools/uml/uml_run.sh --vcan 1 provides vcan0.
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "hal/linux/SocketCanBus.hpp"

namespace carril::hal {
namespace {

CanFrame frame(std::uint32_t id, std::uint8_t tag = 0, std::uint8_t len = 2) {
  CanFrame f;
  f.id = id;
  f.len = len;
  for (std::uint8_t i = 0; i < len; ++i) f.data[i] = std::uint8_t(tag + i);
  return f;
}

// ---- the backlog's deadline logic, without a socket ----

TEST(SocketCanBusTest, BacklogKeepsOrderAndRefusesWhenFull) {
  CanTxBacklog q(2);
  EXPECT_TRUE(q.empty());
  EXPECT_TRUE(q.push(frame(0x101), 0));
  EXPECT_TRUE(q.push(frame(0x102), 1));
  EXPECT_TRUE(q.full());
  EXPECT_FALSE(q.push(frame(0x103), 2));
  EXPECT_EQ(q.front().id, 0x101U);
  q.pop();
  EXPECT_EQ(q.front().id, 0x102U);
  EXPECT_TRUE(q.push(frame(0x104), 3));  // wraps around the ring
  q.pop();
  EXPECT_EQ(q.front().id, 0x104U);
  EXPECT_EQ(q.size(), 1);
}

TEST(SocketCanBusTest, BacklogDropsOnlyFramesPastTheDeadline) {
  CanTxBacklog q(4);
  q.push(frame(0x1), 1000);
  q.push(frame(0x2), 2000);
  q.push(frame(0x3), 3000);
  EXPECT_EQ(q.expire(2000, 1000), 0);  // the oldest is exactly at the deadline: kept
  EXPECT_EQ(q.expire(3500, 1000), 2);  // 0x1 and 0x2 are older than 1000 ns
  ASSERT_EQ(q.size(), 1);
  EXPECT_EQ(q.front().id, 0x3U);
  EXPECT_EQ(q.expire(1'000'000, 1000), 1);
  EXPECT_TRUE(q.empty());
}

// ---- open() refusing bad interfaces (any Linux kernel) ----

TEST(SocketCanBusTest, MissingInterfaceIsNamedInTheError) {
  SocketCanBus::Config c;
  c.iface = "carrilnosuch0";
  const SocketCanBus::OpenResult r = SocketCanBus::open(c);
  EXPECT_EQ(r.bus, nullptr);
  EXPECT_NE(r.error.find("'carrilnosuch0'"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("not found"), std::string::npos) << r.error;
}

TEST(SocketCanBusTest, NonCanInterfaceIsRefused) {
  SocketCanBus::Config c;
  c.iface = "lo";
  const SocketCanBus::OpenResult r = SocketCanBus::open(c);
  EXPECT_EQ(r.bus, nullptr);
  EXPECT_NE(r.error.find("'lo' is not a CAN interface"), std::string::npos) << r.error;
}

TEST(SocketCanBusTest, BadNameAndBadSizesAreRefused) {
  SocketCanBus::Config c;
  c.iface = "";
  EXPECT_NE(SocketCanBus::open(c).error.find("1 to 15 characters"), std::string::npos);
  c.iface = "a_name_far_too_long_for_linux";
  EXPECT_NE(SocketCanBus::open(c).error.find("1 to 15 characters"), std::string::npos);
  c.iface = "vcan0";
  c.tx_backlog = 0;
  const SocketCanBus::OpenResult r = SocketCanBus::open(c);
  EXPECT_EQ(r.bus, nullptr);
  EXPECT_NE(r.error.find("tx_backlog"), std::string::npos) << r.error;
}

// ---- on vcan0 (inside user-mode-linux) ----

constexpr const char* kVcan = "vcan0";

SocketCanBus::Config vcan_config(bool own = false) {
  SocketCanBus::Config c;
  c.iface = kVcan;
  c.receive_own = own;
  return c;
}

std::unique_ptr<SocketCanBus> open_vcan(std::string& why, const SocketCanBus::Config& c) {
  SocketCanBus::OpenResult r = SocketCanBus::open(c);
  why = r.error + " (the vcan tests run in CTest hil_socketcan: tools/uml/uml_run.sh --vcan 1)";
  return std::move(r.bus);
}

std::unique_ptr<SocketCanBus> open_vcan(std::string& why, bool own = false) {
  return open_vcan(why, vcan_config(own));
}

// The kernel delivers a vcan frame from its softirq, which a loaded machine may defer past the
// sender's return: wait up to timeout_ms [ms] for a frame rather than expect it at once.
bool wait_receive(SocketCanBus& bus, CanFrame& out, int timeout_ms = 1000) {
  for (;;) {
    if (bus.receive(out)) return true;
    pollfd p{bus.fd(), POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
  }
}

// OPEN_VCAN_OR_SKIP(bus), (bus, receive_own) or (bus, config): a vcan0 socket, or a skip.
#define OPEN_VCAN_OR_SKIP(var, ...)               \
  std::string var##_why;                          \
  auto var = open_vcan(var##_why, ##__VA_ARGS__); \
  if (!var) GTEST_SKIP() << var##_why

TEST(SocketCanBusTest, VcanFramesGoFromOneSocketToAnother) {
  OPEN_VCAN_OR_SKIP(a);
  OPEN_VCAN_OR_SKIP(b);
  CanFrame ext = frame(0x1ABCDEF0, 9, 8);
  ext.extended = true;
  CanFrame rtr;
  rtr.id = 0x701;
  rtr.rtr = true;
  rtr.len = 1;
  ASSERT_TRUE(a->send(frame(0x181, 3, 6)));
  ASSERT_TRUE(a->send(ext));
  ASSERT_TRUE(a->send(rtr));
  CanFrame got;
  ASSERT_TRUE(wait_receive(*b, got));
  EXPECT_EQ(got.id, 0x181U);
  EXPECT_FALSE(got.extended);
  EXPECT_EQ(got.len, 6);
  EXPECT_EQ(got.data[5], 8);
  ASSERT_TRUE(wait_receive(*b, got));
  EXPECT_EQ(got.id, 0x1ABCDEF0U);
  EXPECT_TRUE(got.extended);
  EXPECT_EQ(got.data[7], 16);
  ASSERT_TRUE(wait_receive(*b, got));
  EXPECT_EQ(got.id, 0x701U);
  EXPECT_TRUE(got.rtr);
  EXPECT_EQ(got.len, 1);
  EXPECT_FALSE(wait_receive(*b, got, 50));
  EXPECT_EQ(a->counters().tx_frames, 3U);
  EXPECT_EQ(b->counters().rx_frames, 3U);
  EXPECT_EQ(a->counters().tx_dropped, 0U);
}

TEST(SocketCanBusTest, VcanOwnFramesOnlyWhenAsked) {
  OPEN_VCAN_OR_SKIP(quiet);
  OPEN_VCAN_OR_SKIP(echo, true);
  CanFrame got;
  ASSERT_TRUE(quiet->send(frame(0x201)));
  ASSERT_TRUE(wait_receive(*echo, got));        // another socket's frame
  EXPECT_FALSE(wait_receive(*quiet, got, 50));  // default: not its own
  EXPECT_EQ(got.id, 0x201U);
  ASSERT_TRUE(echo->send(frame(0x202)));
  ASSERT_TRUE(wait_receive(*echo, got));  // receive_own: its own too
  EXPECT_EQ(got.id, 0x202U);
}

TEST(SocketCanBusTest, VcanReceiveOnEmptyBusReturnsAtOnce) {
  OPEN_VCAN_OR_SKIP(a);
  CanFrame got;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(a->receive(got));
  const auto us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
  // A blocking read would never return; the bound is loose for user-mode-linux's slow system
  // calls on a loaded machine.
  EXPECT_LT(us.count(), 2'000'000) << "10 empty receives took " << us.count() << " us";
  EXPECT_EQ(a->counters().rx_frames, 0U);
}

TEST(SocketCanBusTest, VcanReceiveTakesOneFramePerCall) {
  OPEN_VCAN_OR_SKIP(a);
  OPEN_VCAN_OR_SKIP(b);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(a->send(frame(0x100 + std::uint32_t(i))));
  CanFrame got;
  for (int i = 0; i < 3; ++i) {  // a tick that reads at most 3
    ASSERT_TRUE(wait_receive(*b, got));
    EXPECT_EQ(got.id, 0x100U + std::uint32_t(i));
  }
  EXPECT_EQ(b->counters().rx_frames, 3U);
  int rest = 0;
  while (wait_receive(*b, got, 200)) ++rest;
  EXPECT_EQ(rest, 7);
}

TEST(SocketCanBusTest, VcanInvalidFramesAreRefusedAndCounted) {
  OPEN_VCAN_OR_SKIP(a);
  CanFrame too_long = frame(0x123);
  too_long.len = 9;
  CanFrame too_wide = frame(0x800);  // 12 bits in a standard id
  CanFrame error = frame(kCanErrBusOff);
  error.error = true;
  EXPECT_FALSE(a->send(too_long));
  EXPECT_FALSE(a->send(too_wide));
  EXPECT_FALSE(a->send(error));
  EXPECT_EQ(a->counters().tx_dropped, 3U);
  EXPECT_EQ(a->counters().tx_frames, 0U);
}

TEST(SocketCanBusTest, VcanErrorFramesAreMappedAndCounted) {
  OPEN_VCAN_OR_SKIP(a);
  OPEN_VCAN_OR_SKIP(b);
  // vcan has no controller to report errors: write one as a driver would, through the raw fd.
  can_frame cf{};
  cf.can_id = CAN_ERR_FLAG | CAN_ERR_BUSOFF | CAN_ERR_PROT;
  cf.len = CAN_ERR_DLC;
  cf.data[2] = CAN_ERR_PROT_BIT;
  ASSERT_EQ(::write(a->fd(), &cf, sizeof cf), ssize_t(sizeof cf));
  CanFrame got;
  ASSERT_TRUE(wait_receive(*b, got));
  EXPECT_TRUE(got.error);
  EXPECT_EQ(got.id, kCanErrBusOff | kCanErrProtocol);
  EXPECT_EQ(got.len, 8);
  EXPECT_EQ(got.data[2], CAN_ERR_PROT_BIT);
  EXPECT_EQ(b->counters().error_frames, 1U);
  EXPECT_EQ(b->counters().bus_off, 1U);
  EXPECT_EQ(b->counters().rx_frames, 0U);  // error frames are not data
}

TEST(SocketCanBusTest, VcanReceiveQueueOverrunIsCounted) {
  // One frame per recvmsg and a batch per recvmmsg learn the drops alike.
  for (const int rx_batch : {1, 16}) {
    SCOPED_TRACE("rx_batch " + std::to_string(rx_batch));
    OPEN_VCAN_OR_SKIP(a);
    SocketCanBus::Config c = vcan_config();
    c.rx_batch = rx_batch;
    SocketCanBus::OpenResult rb = SocketCanBus::open(c);
    ASSERT_TRUE(rb.bus) << rb.error;
    SocketCanBus* b = rb.bus.get();
    const int small = 1;  // the kernel rounds it up to its minimum, a few frames
    ASSERT_EQ(::setsockopt(b->fd(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small), 0);
    for (int i = 0; i < 200; ++i) ASSERT_TRUE(a->send(frame(0x300)));
    CanFrame got;
    int n = 0;
    while (wait_receive(*b, got, 200)) ++n;
    EXPECT_GT(n, 0);
    // The kernel tells the drop total with the next frame queued after the drops.
    ASSERT_TRUE(a->send(frame(0x301)));
    ASSERT_TRUE(wait_receive(*b, got));
    EXPECT_EQ(got.id, 0x301U);
    EXPECT_EQ(std::uint64_t(n) + b->counters().rx_dropped, 200U)
        << n << " received, " << b->counters().rx_dropped << " dropped";
  }
}

// Restores vcan0 even when an assertion returns early.
struct LinkUpAtExit {
  ~LinkUpAtExit() { (void)std::system("ip link set up vcan0"); }
};

TEST(SocketCanBusTest, VcanInterfaceDownIsReportedAndReopenRecovers) {
  OPEN_VCAN_OR_SKIP(a);
  OPEN_VCAN_OR_SKIP(b);
  LinkUpAtExit restore;
  ASSERT_EQ(std::system("ip link set down vcan0"), 0);
  EXPECT_FALSE(a->send(frame(0x181)));
  EXPECT_TRUE(a->link_down());
  EXPECT_EQ(a->link_down_events(), 1U);
  EXPECT_EQ(a->counters().tx_dropped, 1U);
  EXPECT_FALSE(a->send(frame(0x182)));
  EXPECT_EQ(a->link_down_events(), 1U);  // one event while it stays down
  CanFrame got;
  EXPECT_FALSE(b->receive(got));  // a receiver learns it too
  EXPECT_TRUE(b->link_down());
  // open() and reopen() say why, naming the interface.
  EXPECT_FALSE(a->reopen());
  EXPECT_NE(a->error().find("'vcan0' is down"), std::string::npos) << a->error();
  ASSERT_EQ(std::system("ip link set up vcan0"), 0);
  ASSERT_TRUE(a->reopen()) << a->error();
  EXPECT_FALSE(a->link_down());
  ASSERT_TRUE(a->send(frame(0x183)));
  ASSERT_TRUE(wait_receive(*b, got));  // b's socket works again once the link is up
  EXPECT_EQ(got.id, 0x183U);
  EXPECT_FALSE(b->link_down());
}

TEST(SocketCanBusTest, VcanBatchedFramesLeaveTogetherAtFlushInOrder) {
  SocketCanBus::Config c = vcan_config();
  c.tx_batch = 8;
  OPEN_VCAN_OR_SKIP(ra, c);
  OPEN_VCAN_OR_SKIP(b);
  SocketCanBus& a = *ra;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(a.send(frame(0x200U + std::uint32_t(i), 2, 6)));
  CanFrame got;
  // Gathered, not sent: nothing on the bus before flush().
  pollfd p{b->fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&p, 1, 50), 0);
  EXPECT_EQ(a.counters().tx_frames, 0U);
  a.flush();
  EXPECT_EQ(a.counters().tx_frames, 5U);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(wait_receive(*b, got)) << i;
    EXPECT_EQ(got.id, 0x200U + std::uint32_t(i));
  }
  // A full batch goes at once; a receive() sends what is gathered (an SDO request waiting for
  // its answer).
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(a.send(frame(0x300U + std::uint32_t(i), 1, 1)));
  EXPECT_EQ(a.counters().tx_frames, 13U);
  ASSERT_TRUE(a.send(frame(0x400, 1, 1)));
  EXPECT_FALSE(a.receive(got));
  EXPECT_EQ(a.counters().tx_frames, 14U);
  for (int i = 0; i < 9; ++i) {
    ASSERT_TRUE(wait_receive(*b, got)) << i;
    EXPECT_EQ(got.id, i < 8 ? 0x300U + std::uint32_t(i) : 0x400U);
  }
}

// rx_batch: the frames queued in the kernel come out of one recvmmsg, in order; a drain ends
// without asking the kernel again, and the next call does ask it.
TEST(SocketCanBusTest, VcanBatchedReceiveTakesTheQueueInOneCallInOrder) {
  SocketCanBus::Config c = vcan_config();
  c.rx_batch = 16;
  OPEN_VCAN_OR_SKIP(rb, c);
  OPEN_VCAN_OR_SKIP(a);
  SocketCanBus& b = *rb;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(a->send(frame(0x500U + std::uint32_t(i))));
  // All ten queued at b before it reads (vcan delivers from a softirq: wait for the last one).
  pollfd p{b.fd(), POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 1000), 1);
  ::usleep(200'000);
  CanFrame got;
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(b.receive(got)) << i;
    EXPECT_EQ(got.id, 0x500U + std::uint32_t(i));
  }
  EXPECT_FALSE(b.receive(got));  // the end of the drain
  EXPECT_EQ(b.receive_calls(), 1U) << "ten queued frames, one system call";
  EXPECT_EQ(b.counters().rx_frames, 10U);
  // The next drain asks the kernel: a frame sent since is there.
  ASSERT_TRUE(a->send(frame(0x5FF)));
  ASSERT_TRUE(wait_receive(b, got));
  EXPECT_EQ(got.id, 0x5FFU);
  EXPECT_GE(b.receive_calls(), 2U);
  // More than a batch: the rest comes with the next call, in order.
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(a->send(frame(0x600U + std::uint32_t(i))));
  int n = 0;
  while (n < 20 && wait_receive(b, got)) {
    EXPECT_EQ(got.id, 0x600U + std::uint32_t(n));
    ++n;
  }
  EXPECT_EQ(n, 20);
  EXPECT_EQ(b.counters().rx_frames, 31U);
}

}  // namespace
}  // namespace carril::hal
