#include "firmware/core/EventLog.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

Event overrun(std::uint32_t count) {
  Event e;
  e.kind = EventKind::Overrun;
  e.task = "t";
  e.count = count;
  return e;
}

TEST(EventLogTest, PopsInOrderPushed) {
  EventLog<4> log;
  EXPECT_EQ(log.size(), 0U);
  EXPECT_EQ(log.capacity(), 4U);
  EXPECT_TRUE(log.push(overrun(1)));
  EXPECT_TRUE(log.push(overrun(2)));
  EXPECT_EQ(log.size(), 2U);
  Event e;
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.count, 1U);
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.count, 2U);
  EXPECT_FALSE(log.pop(e));
  EXPECT_EQ(log.dropped(), 0U);
}

TEST(EventLogTest, FullLogDropsOldestAndCountsIt) {
  EventLog<3> log;
  for (std::uint32_t i = 1; i <= 3; ++i) EXPECT_TRUE(log.push(overrun(i)));
  EXPECT_EQ(log.dropped(), 0U);
  // Two more: events 1 and 2 are overwritten, the newest three are kept.
  EXPECT_FALSE(log.push(overrun(4)));
  EXPECT_FALSE(log.push(overrun(5)));
  EXPECT_EQ(log.dropped(), 2U);
  EXPECT_EQ(log.size(), 3U);
  Event e;
  for (std::uint32_t want = 3; want <= 5; ++want) {
    ASSERT_TRUE(log.pop(e));
    EXPECT_EQ(e.count, want);
  }
  EXPECT_FALSE(log.pop(e));
  // Draining does not forget the drops; room again means no new ones.
  EXPECT_TRUE(log.push(overrun(6)));
  EXPECT_EQ(log.dropped(), 2U);
}

TEST(EventLogTest, UsableThroughTheSinkInterface) {
  EventLog<1> log;
  EventSink& sink = log;
  EXPECT_TRUE(sink.push(overrun(7)));
  EXPECT_FALSE(sink.push(overrun(8)));
  EXPECT_EQ(log.dropped(), 1U);
  Event e;
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.count, 8U);  // newest wins
}

}  // namespace
}  // namespace carril::fw
