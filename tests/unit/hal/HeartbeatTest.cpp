// HeartbeatMonitor: a watched drive's state and boot-ups, its loss after the consumer time
// (latched until heard again), and heartbeats of unknown nodes counted, never acted on.
#include "hal/canopen/Heartbeat.hpp"

#include <gtest/gtest.h>

#include "hal/canopen/Frames.hpp"

namespace carril::hal::canopen {
namespace {

constexpr TimeNs kMs = 1'000'000;

TEST(HeartbeatMonitorTest, TracksStateBootUpsAndLoss) {
  HeartbeatMonitor m;
  ASSERT_TRUE(m.watch(1, 100 * kMs));
  ASSERT_TRUE(m.watch(2, 100 * kMs));
  EXPECT_FALSE(m.watch(2, 100 * kMs));  // already watched
  EXPECT_FALSE(m.watch(0, 100 * kMs));  // no node 0
  EXPECT_FALSE(m.watch(128, 100 * kMs));
  EXPECT_EQ(m.poll(10 * kMs), 0U);  // never heard: not lost (start-up has its own timeout)
  EXPECT_TRUE(m.on_frame(heartbeat(1, NmtState::BootUp), 10 * kMs));
  EXPECT_TRUE(m.on_frame(heartbeat(1, NmtState::PreOperational), 20 * kMs));
  EXPECT_TRUE(m.on_frame(heartbeat(2, NmtState::Operational), 20 * kMs));
  EXPECT_EQ(m.find(1)->boot_ups, 1U);
  EXPECT_EQ(m.find(1)->state, 0x7F);
  EXPECT_EQ(m.poll(120 * kMs), 0U);  // exactly the consumer time: still alive
  EXPECT_TRUE(m.on_frame(heartbeat(2, NmtState::Operational), 110 * kMs));
  EXPECT_EQ(m.poll(121 * kMs), 1U);  // node 1 silent for 101 ms
  EXPECT_TRUE(m.find(1)->lost);
  EXPECT_FALSE(m.find(2)->lost);
  EXPECT_EQ(m.poll(130 * kMs), 1U);  // latched, counted once
  EXPECT_EQ(m.find(1)->losses, 1U);
  EXPECT_TRUE(m.on_frame(heartbeat(1, NmtState::BootUp), 140 * kMs));  // it restarted
  EXPECT_FALSE(m.find(1)->lost);
  EXPECT_EQ(m.find(1)->boot_ups, 2U);
  EXPECT_EQ(m.poll(150 * kMs), 0U);
}

TEST(HeartbeatMonitorTest, UnknownNodesAndOtherFramesAreIgnored) {
  HeartbeatMonitor m;
  ASSERT_TRUE(m.watch(1, 100 * kMs));
  EXPECT_FALSE(m.on_frame(heartbeat(7, NmtState::Operational), 0));
  EXPECT_EQ(m.unknown(), 1U);
  EXPECT_FALSE(m.on_frame(sync_frame(), 0));
  EXPECT_FALSE(m.on_frame(rpdo1(1, 0x0F, 0), 0));
  EXPECT_EQ(m.unknown(), 1U);
  EXPECT_FALSE(m.find(1)->heard);
}

TEST(HeartbeatMonitorTest, HoldsAFixedNumberOfNodes) {
  HeartbeatMonitor m;
  for (std::uint8_t i = 1; i <= HeartbeatMonitor::kMaxNodes; ++i) EXPECT_TRUE(m.watch(i, kMs));
  EXPECT_FALSE(m.watch(100, kMs));
  EXPECT_EQ(m.size(), HeartbeatMonitor::kMaxNodes);
}

}  // namespace
}  // namespace carril::hal::canopen
