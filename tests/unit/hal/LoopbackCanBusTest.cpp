#include <gtest/gtest.h>

#include <vector>

#include "hal/can/LoopbackCanBus.hpp"

namespace carril::hal {
namespace {

CanFrame frame(std::uint32_t id, std::uint8_t tag = 0) {
  CanFrame f;
  f.id = id;
  f.len = 2;
  f.data[0] = tag;
  f.data[1] = 0xA5;
  return f;
}

// Everything endpoint `ep` has waiting, oldest first.
std::vector<CanFrame> drain(CanBus& ep) {
  std::vector<CanFrame> out;
  CanFrame f;
  while (ep.receive(f)) out.push_back(f);
  return out;
}

std::vector<std::uint32_t> ids(const std::vector<CanFrame>& frames) {
  std::vector<std::uint32_t> out;
  for (const CanFrame& f : frames) out.push_back(f.id);
  return out;
}

LoopbackCanBus::Config three_nodes() {
  LoopbackCanBus::Config c;
  c.endpoints = 3;
  return c;
}

TEST(LoopbackCanBusTest, StartsQuiet) {
  LoopbackCanBus bus(three_nodes());
  EXPECT_EQ(bus.endpoints(), 3);
  EXPECT_EQ(bus.transfer(), 0);
  for (int i = 0; i < 3; ++i) {
    CanFrame f;
    EXPECT_FALSE(bus.endpoint(i).receive(f)) << i;
    const CanBusCounters c = bus.endpoint(i).counters();
    EXPECT_EQ(c.tx_frames + c.rx_frames + c.tx_dropped + c.rx_dropped, 0U) << i;
    EXPECT_EQ(c.error_frames + c.bus_off, 0U) << i;
    EXPECT_FALSE(bus.bus_off(i)) << i;
  }
}

TEST(LoopbackCanBusTest, DeliversToEveryOtherEndpointNotToSelf) {
  LoopbackCanBus bus(three_nodes());
  CanFrame sent;
  sent.id = 0x1ABCDE0;
  sent.extended = true;
  sent.len = 8;
  for (std::uint8_t i = 0; i < 8; ++i) sent.data[i] = std::uint8_t(0x10 + i);
  ASSERT_TRUE(bus.endpoint(0).send(sent));
  CanFrame got;
  EXPECT_FALSE(bus.endpoint(1).receive(got));  // nothing arrives before bus time passes
  EXPECT_EQ(bus.transfer(), 1);

  for (int i : {1, 2}) {
    ASSERT_TRUE(bus.endpoint(i).receive(got)) << i;
    EXPECT_EQ(got.id, sent.id);
    EXPECT_TRUE(got.extended);
    EXPECT_FALSE(got.rtr);
    EXPECT_FALSE(got.error);
    EXPECT_EQ(got.len, 8);
    for (int b = 0; b < 8; ++b) EXPECT_EQ(got.data[b], sent.data[b]) << b;
    EXPECT_FALSE(bus.endpoint(i).receive(got)) << i;  // exactly once
    EXPECT_EQ(bus.endpoint(i).counters().rx_frames, 1U) << i;
  }
  EXPECT_FALSE(bus.endpoint(0).receive(got));  // not to the sender
  EXPECT_EQ(bus.endpoint(0).counters().tx_frames, 1U);
  EXPECT_EQ(bus.endpoint(0).counters().rx_frames, 0U);
}

// Two nodes talking at once: each must hear exactly the other's frames. Fails if a sender
// received its own frames (counts and ids would both be off).
TEST(LoopbackCanBusTest, SenderNeverHearsItself) {
  LoopbackCanBus bus({});
  for (std::uint8_t k = 0; k < 5; ++k) ASSERT_TRUE(bus.endpoint(0).send(frame(0x200, k)));
  for (std::uint8_t k = 0; k < 3; ++k) ASSERT_TRUE(bus.endpoint(1).send(frame(0x180, k)));
  EXPECT_EQ(bus.transfer(), 8);
  EXPECT_EQ(ids(drain(bus.endpoint(0))), std::vector<std::uint32_t>(3, 0x180));
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>(5, 0x200));
  EXPECT_EQ(bus.endpoint(0).counters().rx_frames, 3U);
  EXPECT_EQ(bus.endpoint(1).counters().rx_frames, 5U);
}

TEST(LoopbackCanBusTest, OwnEchoWhenAskedFor) {
  LoopbackCanBus::Config c;
  c.own_echo = true;
  LoopbackCanBus bus(c);
  ASSERT_TRUE(bus.endpoint(0).send(frame(0x123)));
  bus.transfer();
  EXPECT_EQ(ids(drain(bus.endpoint(0))), std::vector<std::uint32_t>{0x123});
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>{0x123});
}

TEST(LoopbackCanBusTest, OneNodesFramesKeepSendOrder) {
  // Descending ids: arbitration would reverse them, a node's FIFO must not.
  LoopbackCanBus bus({});
  const std::vector<std::uint32_t> order = {0x700, 0x381, 0x201, 0x080, 0x000};
  for (std::uint32_t id : order) ASSERT_TRUE(bus.endpoint(0).send(frame(id)));
  bus.transfer();
  EXPECT_EQ(ids(drain(bus.endpoint(1))), order);
}

TEST(LoopbackCanBusTest, ArbitrationOrdersFramesOfDifferentNodes) {
  LoopbackCanBus::Config c;
  c.endpoints = 4;
  LoopbackCanBus bus(c);
  ASSERT_TRUE(bus.endpoint(0).send(frame(0x181)));
  ASSERT_TRUE(bus.endpoint(0).send(frame(0x050)));  // waits behind 0x181 on its own node
  ASSERT_TRUE(bus.endpoint(1).send(frame(0x700)));
  ASSERT_TRUE(bus.endpoint(2).send(frame(0x080)));
  bus.transfer();
  EXPECT_EQ(ids(drain(bus.endpoint(3))), (std::vector<std::uint32_t>{0x080, 0x181, 0x050, 0x700}));
}

TEST(LoopbackCanBusTest, ArbitrationStandardBeforeExtendedDataBeforeRemote) {
  LoopbackCanBus::Config c;
  c.endpoints = 4;
  LoopbackCanBus bus(c);
  CanFrame ext = frame(0x123U << 18);  // same base id as the standard frame 0x123
  ext.extended = true;
  CanFrame remote = frame(0x123);
  remote.rtr = true;
  remote.len = 0;
  ASSERT_TRUE(bus.endpoint(0).send(ext));
  ASSERT_TRUE(bus.endpoint(1).send(remote));
  ASSERT_TRUE(bus.endpoint(2).send(frame(0x123)));
  bus.transfer();
  const std::vector<CanFrame> got = drain(bus.endpoint(3));
  ASSERT_EQ(got.size(), 3U);
  EXPECT_TRUE(!got[0].extended && !got[0].rtr);  // standard data frame
  EXPECT_TRUE(!got[1].extended && got[1].rtr);   // standard remote frame
  EXPECT_TRUE(got[2].extended);
}

TEST(LoopbackCanBusTest, TransferLimitsFramesPerCall) {
  LoopbackCanBus bus({});
  for (std::uint32_t id = 1; id <= 3; ++id) ASSERT_TRUE(bus.endpoint(0).send(frame(id)));
  EXPECT_EQ(bus.transfer(2), 2);
  EXPECT_EQ(drain(bus.endpoint(1)).size(), 2U);
  EXPECT_EQ(bus.transfer(), 1);
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>{3});
}

TEST(LoopbackCanBusTest, FullTransmitQueueRefusesAndCounts) {
  LoopbackCanBus::Config c;
  c.tx_depth = 4;
  LoopbackCanBus bus(c);
  for (std::uint32_t id = 1; id <= 4; ++id) EXPECT_TRUE(bus.endpoint(0).send(frame(id))) << id;
  EXPECT_FALSE(bus.endpoint(0).send(frame(5)));
  EXPECT_FALSE(bus.endpoint(0).send(frame(6)));
  EXPECT_EQ(bus.endpoint(0).counters().tx_dropped, 2U);
  EXPECT_EQ(bus.transfer(), 4);
  EXPECT_EQ(ids(drain(bus.endpoint(1))), (std::vector<std::uint32_t>{1, 2, 3, 4}));
  EXPECT_EQ(bus.endpoint(0).counters().tx_frames, 4U);
  EXPECT_TRUE(bus.endpoint(0).send(frame(7)));  // room again
}

TEST(LoopbackCanBusTest, ReceiveOverrunKeepsTheOldestAndCounts) {
  LoopbackCanBus::Config c;
  c.rx_depth = 3;
  LoopbackCanBus bus(c);
  for (std::uint32_t id = 1; id <= 5; ++id) ASSERT_TRUE(bus.endpoint(0).send(frame(id)));
  bus.transfer();
  EXPECT_EQ(bus.endpoint(1).counters().rx_dropped, 2U);
  EXPECT_EQ(ids(drain(bus.endpoint(1))), (std::vector<std::uint32_t>{1, 2, 3}));
  EXPECT_EQ(bus.endpoint(1).counters().rx_frames, 3U);
  EXPECT_EQ(bus.endpoint(0).counters().rx_dropped, 0U);
}

TEST(LoopbackCanBusTest, InvalidFramesAreRefused) {
  LoopbackCanBus bus({});
  CanFrame too_long = frame(0x100);
  too_long.len = 9;
  CanFrame wide_std = frame(0x800);
  CanFrame wide_ext = frame(0x20000000);
  wide_ext.extended = true;
  CanFrame error = frame(0x100);
  error.error = true;  // only controllers report error frames
  for (const CanFrame& f : {too_long, wide_std, wide_ext, error}) {
    EXPECT_FALSE(bus.endpoint(0).send(f));
  }
  EXPECT_EQ(bus.endpoint(0).counters().tx_dropped, 4U);
  CanFrame widest = frame(kCanExtIdMask);
  widest.extended = true;
  EXPECT_TRUE(bus.endpoint(0).send(widest));
  EXPECT_TRUE(bus.endpoint(0).send(frame(kCanStdIdMask)));
  EXPECT_EQ(bus.transfer(), 2);
}

TEST(LoopbackCanBusTest, DropNextLosesFramesOnTheWire) {
  LoopbackCanBus bus(three_nodes());
  bus.drop_next(2);
  for (std::uint32_t id = 1; id <= 3; ++id) ASSERT_TRUE(bus.endpoint(0).send(frame(id)));
  EXPECT_EQ(bus.transfer(), 3);
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>{3});
  EXPECT_EQ(ids(drain(bus.endpoint(2))), std::vector<std::uint32_t>{3});
  EXPECT_EQ(bus.endpoint(0).counters().tx_frames, 3U);  // the sender did transmit them
  EXPECT_EQ(bus.frames_lost(), 2U);
  ASSERT_TRUE(bus.endpoint(0).send(frame(4)));  // the drops are used up
  bus.transfer();
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>{4});
}

TEST(LoopbackCanBusTest, ErrorFrameReachesEveryNodeAndIsCounted) {
  LoopbackCanBus bus(three_nodes());
  bus.inject_error_frame();
  for (int i = 0; i < 3; ++i) {
    const std::vector<CanFrame> got = drain(bus.endpoint(i));
    ASSERT_EQ(got.size(), 1U) << i;
    EXPECT_TRUE(got[0].error) << i;
    EXPECT_EQ(got[0].id, kCanErrProtocol) << i;
    const CanBusCounters c = bus.endpoint(i).counters();
    EXPECT_EQ(c.error_frames, 1U) << i;
    EXPECT_EQ(c.rx_frames, 0U) << i;  // error frames are not traffic
  }
}

TEST(LoopbackCanBusTest, BusOffRefusesSendsAndHearsNothingUntilRestart) {
  LoopbackCanBus bus(three_nodes());
  ASSERT_TRUE(bus.endpoint(1).send(frame(0x201)));  // queued when the node drops out
  bus.force_bus_off(1);
  EXPECT_TRUE(bus.bus_off(1));
  CanBusCounters c = bus.endpoint(1).counters();
  EXPECT_EQ(c.bus_off, 1U);
  EXPECT_EQ(c.tx_dropped, 1U);  // the queued frame was discarded
  std::vector<CanFrame> got = drain(bus.endpoint(1));
  ASSERT_EQ(got.size(), 1U);
  EXPECT_TRUE(got[0].error);
  EXPECT_EQ(got[0].id, kCanErrBusOff);
  EXPECT_EQ(bus.endpoint(1).counters().error_frames, 1U);

  EXPECT_FALSE(bus.endpoint(1).send(frame(0x202)));
  EXPECT_EQ(bus.endpoint(1).counters().tx_dropped, 2U);
  ASSERT_TRUE(bus.endpoint(0).send(frame(0x181)));
  bus.inject_error_frame();
  EXPECT_EQ(bus.transfer(), 1);                 // the discarded 0x201 never reaches the wire
  EXPECT_TRUE(drain(bus.endpoint(1)).empty());  // off the bus: neither traffic nor errors
  EXPECT_EQ(drain(bus.endpoint(2)).size(), 2U);
  EXPECT_EQ(drain(bus.endpoint(0)).size(), 1U);  // the error frame
  bus.force_bus_off(1);                          // already off: not a new event
  EXPECT_EQ(bus.endpoint(1).counters().bus_off, 1U);
  EXPECT_EQ(bus.endpoint(0).counters().bus_off, 0U);  // only that node

  bus.restart(1);
  EXPECT_FALSE(bus.bus_off(1));
  ASSERT_TRUE(bus.endpoint(1).send(frame(0x203)));
  ASSERT_TRUE(bus.endpoint(0).send(frame(0x182)));
  bus.transfer();
  EXPECT_EQ(ids(drain(bus.endpoint(0))), std::vector<std::uint32_t>{0x203});
  EXPECT_EQ(ids(drain(bus.endpoint(1))), std::vector<std::uint32_t>{0x182});
  c = bus.endpoint(1).counters();
  EXPECT_EQ(c.bus_off, 1U);
  EXPECT_EQ(c.tx_frames, 1U);
}

}  // namespace
}  // namespace carril::hal
