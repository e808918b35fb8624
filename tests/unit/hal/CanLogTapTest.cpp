#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hal/can/CanLogTap.hpp"
#include "hal/can/Candump.hpp"
#include "hal/can/LoopbackCanBus.hpp"

namespace carril::hal {
namespace {

CanFrame frame(std::uint32_t id, std::uint8_t len, std::uint8_t tag) {
  CanFrame f;
  f.id = id;
  f.len = len;
  for (std::uint8_t i = 0; i < len; ++i) f.data[i] = std::uint8_t(tag + i);
  return f;
}

// A clock the test moves by hand.
struct FakeTime {
  TimeNs t = 1'436'509'052'249'713'000;
  static TimeNs now(void* self) { return static_cast<FakeTime*>(self)->t; }
};

std::vector<std::string> drain_lines(CanLogTap& tap, std::size_t max = SIZE_MAX) {
  std::vector<std::string> lines;
  tap.drain([&](const char* s, std::size_t n) { lines.emplace_back(s, n); }, max);
  return lines;
}

TEST(CanLogTapTest, RecordsSentAndReceivedFramesWithTheirTimes) {
  LoopbackCanBus bus({});
  FakeTime clock;
  CanLogTap tap(bus.endpoint(0), 8, "can0", &FakeTime::now, &clock);
  const CanFrame out = frame(0x201, 6, 1);
  ASSERT_TRUE(tap.send(out));
  bus.transfer();
  clock.t += 1'000'000;  // 1 ms later the drive answers
  CanFrame in = frame(0x181, 6, 7);
  in.extended = false;
  ASSERT_TRUE(bus.endpoint(1).send(in));
  bus.transfer();
  CanFrame got;
  ASSERT_TRUE(tap.receive(got));
  EXPECT_FALSE(tap.receive(got));  // nothing more: nothing recorded
  EXPECT_EQ(tap.recorded(), 2U);
  EXPECT_EQ(tap.pending(), 2U);

  const std::vector<std::string> lines = drain_lines(tap);
  ASSERT_EQ(lines.size(), 2U);
  EXPECT_EQ(lines[0], "(1436509052.249713) can0 201#010203040506\n");
  EXPECT_EQ(lines[1], "(1436509052.250713) can0 181#0708090A0B0C\n");
  CanFrame back;
  TimeNs t = 0;
  ASSERT_TRUE(parse_candump(lines[1].c_str(), back, t));
  EXPECT_EQ(back.id, 0x181U);
  EXPECT_EQ(t, clock.t);
  EXPECT_EQ(tap.pending(), 0U);
}

TEST(CanLogTapTest, TellsDirectionAndPassesCountersThrough) {
  LoopbackCanBus bus({});
  CanLogTap tap(bus.endpoint(0), 8, "can0", nullptr, nullptr);
  ASSERT_TRUE(tap.send(frame(0x100, 1, 0)));
  ASSERT_TRUE(bus.endpoint(1).send(frame(0x101, 1, 0)));
  bus.transfer();
  CanFrame got;
  ASSERT_TRUE(tap.receive(got));
  CanLogTap::Record r;
  ASSERT_TRUE(tap.pop(r));
  EXPECT_TRUE(r.tx);
  EXPECT_EQ(r.frame.id, 0x100U);
  ASSERT_TRUE(tap.pop(r));
  EXPECT_FALSE(r.tx);
  EXPECT_EQ(r.frame.id, 0x101U);
  EXPECT_EQ(tap.counters().tx_frames, 1U);
  EXPECT_EQ(tap.counters().rx_frames, 1U);
}

TEST(CanLogTapTest, FramesTheInnerBusRefusesAreNotRecorded) {
  LoopbackCanBus bus({});
  CanLogTap tap(bus.endpoint(0), 8, "can0", nullptr, nullptr);
  CanFrame bad = frame(0x123, 2, 0);
  bad.len = 9;
  EXPECT_FALSE(tap.send(bad));
  EXPECT_EQ(tap.recorded(), 0U);
  EXPECT_EQ(tap.counters().tx_dropped, 1U);
}

TEST(CanLogTapTest, AFullRingDropsAndCountsWithoutTouchingTheBus) {
  LoopbackCanBus bus({});
  CanLogTap tap(bus.endpoint(0), 2, "can0", nullptr, nullptr);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(tap.send(frame(0x200 + std::uint32_t(i), 1, 0)));
  EXPECT_EQ(tap.recorded(), 2U);
  EXPECT_EQ(tap.dropped(), 3U);
  EXPECT_EQ(bus.transfer(), 5);  // all five went on the bus
  const std::vector<std::string> first = drain_lines(tap, 1);
  ASSERT_EQ(first.size(), 1U);
  EXPECT_NE(first[0].find(" 200#"), std::string::npos) << first[0];
  EXPECT_TRUE(tap.send(frame(0x2FF, 1, 0)));  // one slot free again
  const std::vector<std::string> rest = drain_lines(tap);
  ASSERT_EQ(rest.size(), 2U);
  EXPECT_NE(rest[0].find(" 201#"), std::string::npos) << rest[0];
  EXPECT_NE(rest[1].find(" 2FF#"), std::string::npos) << rest[1];
  EXPECT_EQ(tap.dropped(), 3U);
}

// Accepts everything: the producer's side of the concurrent test.
class SinkBus final : public CanBus {
 public:
  bool send(const CanFrame&) override { return true; }
  bool receive(CanFrame&) override { return false; }
  CanBusCounters counters() const override { return {}; }
};

TEST(CanLogTapTest, AWriterThreadDrainsWhileTheTickRecords) {
  SinkBus sink;
  CanLogTap tap(sink, 256, "can0", nullptr, nullptr);
  constexpr std::uint32_t kFrames = 200'000;
  std::atomic<bool> done{false};
  std::thread tick([&] {
    for (std::uint32_t i = 0; i < kFrames; ++i) {
      CanFrame f = frame(0x181, 4, 0);
      for (int b = 0; b < 4; ++b) f.data[b] = std::uint8_t(i >> (8 * b));  // sequence number
      tap.send(f);
    }
    done = true;
  });
  std::uint64_t drained = 0;
  std::int64_t last = -1;
  bool in_order = true;
  CanLogTap::Record r;
  for (;;) {
    const bool finished = done.load();
    while (tap.pop(r)) {
      const std::int64_t seq = std::int64_t(r.frame.data[0] | r.frame.data[1] << 8 |
                                            r.frame.data[2] << 16 | r.frame.data[3] << 24);
      in_order = in_order && seq > last;
      last = seq;
      ++drained;
    }
    if (finished) break;
  }
  tick.join();
  EXPECT_TRUE(in_order);
  EXPECT_GT(drained, 0U);
  EXPECT_EQ(drained + tap.dropped(), kFrames);
  EXPECT_EQ(tap.recorded(), drained);
}

// can-utils reads what drain() writes.
TEST(CanLogTapTest, Log2ascReadsTheLog) {
  if (std::system("command -v log2asc >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "log2asc not installed (apt-get install can-utils)";
  }
  LoopbackCanBus bus({});
  FakeTime clock;
  CanLogTap tap(bus.endpoint(0), 16, "vcan0", &FakeTime::now, &clock);
  tap.send(frame(0x201, 6, 1));
  CanFrame ext = frame(0x12345678, 8, 0xF0);
  ext.extended = true;
  clock.t += 250'000;
  tap.send(ext);
  CanFrame rtr;
  rtr.id = 0x701;
  rtr.rtr = true;
  rtr.len = 1;
  clock.t += 250'000;
  tap.send(rtr);
  const std::string dir = ::testing::TempDir();
  const std::string log = dir + "carril_can_log_" + std::to_string(::getpid()) + ".log";
  const std::string asc = log + ".asc";
  {
    std::ofstream f(log);
    tap.drain([&](const char* s, std::size_t n) { f.write(s, std::streamsize(n)); });
  }
  ASSERT_EQ(std::system(("log2asc -I " + log + " -O " + asc + " vcan0").c_str()), 0);
  std::ifstream in(asc);
  std::stringstream text;
  text << in.rdbuf();
  const std::string a = text.str();
  std::remove(log.c_str());
  std::remove(asc.c_str());
  EXPECT_NE(a.find("0.000000 1  201             Rx   d 6 01 02 03 04 05 06"), std::string::npos)
      << a;
  EXPECT_NE(a.find("0.000250 1  12345678x       Rx   d 8 F0 F1 F2 F3 F4 F5 F6 F7"),
            std::string::npos)
      << a;
  EXPECT_NE(a.find("0.000500 1  701             Rx   r 1"), std::string::npos) << a;
}

}  // namespace
}  // namespace carril::hal
