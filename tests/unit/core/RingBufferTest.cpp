#include "firmware/core/RingBuffer.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

static_assert(RingBuffer<int, 5>{}.capacity() == 5);

TEST(RingBufferTest, FifoOrder) {
  RingBuffer<int, 4> rb;
  EXPECT_TRUE(rb.empty());
  EXPECT_TRUE(rb.push(1));
  EXPECT_TRUE(rb.push(2));
  EXPECT_TRUE(rb.push(3));
  EXPECT_EQ(rb.size(), 3U);
  int out = 0;
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 1);
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 2);
  EXPECT_TRUE(rb.push(4));
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 3);
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 4);
  EXPECT_TRUE(rb.empty());
}

TEST(RingBufferTest, PopOnEmptyReturnsFalseAndLeavesOutput) {
  RingBuffer<int, 2> rb;
  int out = -7;
  EXPECT_FALSE(rb.pop(out));
  EXPECT_EQ(out, -7);
  rb.push(5);
  ASSERT_TRUE(rb.pop(out));
  EXPECT_FALSE(rb.pop(out));
  EXPECT_EQ(out, 5);
  EXPECT_EQ(rb.size(), 0U);
}

TEST(RingBufferTest, OverwritesOldestWhenFull) {
  RingBuffer<int, 3> rb;
  EXPECT_TRUE(rb.push(1));
  EXPECT_TRUE(rb.push(2));
  EXPECT_TRUE(rb.push(3));
  EXPECT_TRUE(rb.full());
  EXPECT_FALSE(rb.push(4));  // 1 is dropped
  EXPECT_FALSE(rb.push(5));  // 2 is dropped
  EXPECT_EQ(rb.size(), 3U);
  EXPECT_TRUE(rb.full());
  int out = 0;
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 3);
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 4);
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 5);
  EXPECT_FALSE(rb.pop(out));
}

TEST(RingBufferTest, IndexIsOldestFirstAcrossWrap) {
  RingBuffer<int, 4> rb;
  for (int i = 1; i <= 6; ++i) rb.push(i);  // holds 3, 4, 5, 6 with the head wrapped
  ASSERT_EQ(rb.size(), 4U);
  EXPECT_EQ(rb[0], 3);
  EXPECT_EQ(rb[1], 4);
  EXPECT_EQ(rb[2], 5);
  EXPECT_EQ(rb[3], 6);
  EXPECT_EQ(rb.newest(), 6);
}

TEST(RingBufferTest, NewestTracksLastPush) {
  RingBuffer<int, 2> rb;
  rb.push(10);
  EXPECT_EQ(rb.newest(), 10);
  EXPECT_EQ(rb[0], 10);
  rb.push(20);
  EXPECT_EQ(rb.newest(), 20);
  rb.push(30);
  EXPECT_EQ(rb.newest(), 30);
  EXPECT_EQ(rb[0], 20);
  int out = 0;
  rb.pop(out);
  EXPECT_EQ(rb.newest(), 30);
  EXPECT_EQ(rb[0], 30);
}

TEST(RingBufferTest, ClearResets) {
  RingBuffer<int, 3> rb;
  for (int i = 0; i < 5; ++i) rb.push(i);
  rb.clear();
  EXPECT_TRUE(rb.empty());
  EXPECT_EQ(rb.size(), 0U);
  int out = 0;
  EXPECT_FALSE(rb.pop(out));
  EXPECT_TRUE(rb.push(9));
  EXPECT_EQ(rb[0], 9);
  EXPECT_EQ(rb.newest(), 9);
}

TEST(RingBufferTest, CapacityOne) {
  RingBuffer<int, 1> rb;
  EXPECT_TRUE(rb.push(1));
  EXPECT_FALSE(rb.push(2));
  EXPECT_EQ(rb.size(), 1U);
  EXPECT_EQ(rb.newest(), 2);
  int out = 0;
  ASSERT_TRUE(rb.pop(out));
  EXPECT_EQ(out, 2);
}

}  // namespace
}  // namespace carril::fw
