#include "hal/TripleBuffer.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

namespace carril::hal {
namespace {

TEST(TripleBufferTest, NothingBeforeTheFirstPublish) {
  TripleBuffer<int> b;
  EXPECT_FALSE(b.fetch());
  EXPECT_EQ(b.seq(), 0U);
  EXPECT_EQ(b.value(), 0);
}

TEST(TripleBufferTest, ReaderGetsTheNewestValueOnce) {
  TripleBuffer<int> b;
  b.write(10);
  ASSERT_TRUE(b.fetch());
  EXPECT_EQ(b.value(), 10);
  EXPECT_EQ(b.seq(), 1U);
  EXPECT_FALSE(b.fetch());  // nothing new: the value and seq stay
  EXPECT_EQ(b.value(), 10);
  EXPECT_EQ(b.seq(), 1U);
  // Three published before the reader looks: it gets the newest, and seq says two were missed.
  b.write(20);
  b.write(30);
  b.write(40);
  EXPECT_EQ(b.value(), 10);  // unchanged until fetched
  ASSERT_TRUE(b.fetch());
  EXPECT_EQ(b.value(), 40);
  EXPECT_EQ(b.seq(), 4U);
  EXPECT_FALSE(b.fetch());
  EXPECT_EQ(b.value(), 40);
}

TEST(TripleBufferTest, WriteSlotIsFilledInPlace) {
  struct Pose {
    double x = 0, y = 0;
  };
  TripleBuffer<Pose> b;
  Pose& p = b.write_slot();
  p.x = 1.5;
  p.y = -2.0;
  EXPECT_FALSE(b.fetch());  // not published yet
  b.publish();
  ASSERT_TRUE(b.fetch());
  EXPECT_EQ(b.value().x, 1.5);
  EXPECT_EQ(b.value().y, -2.0);
}

// Fields all equal to the sequence number they were published with: a torn read shows as a
// mismatch. Large enough that a copy takes many instructions.
struct Block {
  std::uint64_t f[32];
};

// One writer and one reader thread hammer the buffer; the reader must never see a torn block,
// and seq must only go up. Runs until the reader has taken many values (not a fixed number of
// writes: on a busy machine a writer can finish a million writes before the reader runs).
TEST(TripleBufferTest, TwoThreadsNeverSeeATornValue) {
  constexpr std::uint64_t kFetches = 20'000;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  auto b = std::make_unique<TripleBuffer<Block>>();
  std::atomic<bool> stop{false};
  std::uint64_t written = 0;  // the writer's; read after join()

  std::thread writer([&] {
    while (!stop.load(std::memory_order_relaxed)) {
      const std::uint64_t i = written + 1;
      Block& s = b->write_slot();
      for (std::uint64_t& f : s.f) f = i;  // field by field, as real code fills a slot
      b->publish();
      written = i;
    }
  });

  std::uint64_t fetched = 0, torn = 0, backwards = 0, seq_mismatch = 0, last = 0;
  auto check = [&] {
    const Block copy = b->value();
    const std::uint64_t seq = b->seq();
    ++fetched;
    for (const std::uint64_t f : copy.f) {
      if (f != copy.f[0]) {
        ++torn;
        break;
      }
    }
    if (copy.f[0] != seq) ++seq_mismatch;
    if (seq <= last) ++backwards;  // fetch() said new: strictly greater
    last = seq;
  };
  while (fetched < kFetches && std::chrono::steady_clock::now() < give_up) {
    if (b->fetch()) check();
  }
  stop.store(true, std::memory_order_relaxed);
  writer.join();
  if (b->fetch()) check();  // the last value, if not taken yet

  EXPECT_EQ(torn, 0U);
  EXPECT_EQ(seq_mismatch, 0U);
  EXPECT_EQ(backwards, 0U);
  EXPECT_EQ(last, written);  // the reader ends on the newest value
  EXPECT_FALSE(b->fetch());
  // Not a timing check: the test means little unless the two threads interleaved at all.
  EXPECT_GT(fetched, 100U) << "written " << written;
  RecordProperty("fetched", std::to_string(fetched));
  RecordProperty("written", std::to_string(written));
}

}  // namespace
}  // namespace carril::hal
