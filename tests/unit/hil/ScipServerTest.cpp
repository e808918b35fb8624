#include "host_sim/hil/ScipServer.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace carril::sim {
namespace {

namespace scip = hal::scip;
constexpr double kDeg = M_PI / 180.0;

// A UST-10LX's shape: 270 deg in 0.25 deg steps, 0.02 to 30 m.
hal::LaserScan ust_shape() {
  hal::LaserScan s;
  s.count = 1081;
  s.angle_min_rad = float(-135.0 * kDeg);
  s.angle_increment_rad = float(0.25 * kDeg);
  s.range_min_m = 0.02F;
  s.range_max_m = 30.0F;
  for (int i = 0; i < s.count; ++i) s.ranges_m[std::size_t(i)] = 0.5F + 0.01F * float(i);
  return s;
}

// A bare TCP client: sends command lines, reads whole messages.
class Client {
 public:
  explicit Client(std::uint16_t port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ok_ = connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~Client() { close(fd_); }
  bool ok() const { return ok_; }
  void send_line(const std::string& s) {
    const std::string l = s + "\n";
    ASSERT_EQ(::send(fd_, l.data(), l.size(), MSG_NOSIGNAL), ssize_t(l.size()));
  }
  // The next message (up to and including its empty line), "" after timeout_ms.
  std::string message(int timeout_ms = 1000) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
      const std::size_t end = buf_.find("\n\n");
      if (end != std::string::npos) {
        std::string m = buf_.substr(0, end + 2);
        buf_.erase(0, end + 2);
        return m;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return "";
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, int(left.count())) <= 0) continue;
      char tmp[4096];
      const ssize_t k = recv(fd_, tmp, sizeof tmp, 0);
      if (k <= 0) return "";
      buf_.append(tmp, std::size_t(k));
    }
  }

 private:
  int fd_ = -1;
  bool ok_ = false;
  std::string buf_;
};

class ScipServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* why = "";
    ASSERT_TRUE(ScipServer::geometry_for(ust_shape(), 2400, cfg_.geometry, why)) << why;
    cfg_.port = 0;
    ASSERT_TRUE(server_.start(cfg_)) << server_.error();
  }
  ScipServerConfig cfg_;
  ScipServer server_;
};

scip::Lines lines_of(const std::string& m) {
  scip::Lines l;
  EXPECT_TRUE(scip::split_lines(m.data(), m.size(), l)) << m;
  return l;
}

TEST(ScipServerGeometry, FromTheScanShape) {
  scip::Geometry g;
  const char* why = "";
  ASSERT_TRUE(ScipServer::geometry_for(ust_shape(), 2400, g, why)) << why;
  EXPECT_EQ(g.ares, 1440);
  EXPECT_EQ(g.amin, 0);
  EXPECT_EQ(g.amax, 1080);
  EXPECT_EQ(g.afrt, 540);
  EXPECT_EQ(g.dmin_mm, 20);
  EXPECT_EQ(g.dmax_mm, 30000);
  hal::LaserScan odd = ust_shape();
  odd.angle_increment_rad = float(0.3 * kDeg) * 1.01F;
  EXPECT_FALSE(ScipServer::geometry_for(odd, 2400, g, why));
  EXPECT_NE(std::string(why).find("whole steps"), std::string::npos);
  ScipServer s;
  ScipServerConfig bad;
  EXPECT_FALSE(s.start(bad));
  EXPECT_NE(std::string(s.error()).find("geometry"), std::string::npos);
}

TEST_F(ScipServerTest, AnswersVvPpIiWithSumsThatCheck) {
  Client c(server_.port());
  ASSERT_TRUE(c.ok());
  c.send_line("VV");
  std::string m = c.message();
  const char* why = "";
  char value[64];
  scip::Lines l = lines_of(m);
  ASSERT_TRUE(scip::parse_info_reply(l, scip::Command::VV, "PROD", value, sizeof value, why))
      << why << "\n"
      << m;
  EXPECT_STREQ(value, "UST-10LX");
  EXPECT_EQ(m.rfind("VV\n00P\n", 0), 0U);

  c.send_line("PP");
  m = c.message();
  l = lines_of(m);
  scip::Geometry g;
  ASSERT_TRUE(scip::parse_pp(l, g, why)) << why << "\n" << m;
  EXPECT_EQ(g.ares, 1440);
  EXPECT_EQ(g.afrt, 540);
  EXPECT_EQ(g.amax, 1080);
  EXPECT_EQ(g.scan_rpm, 2400);

  c.send_line("II;tag1");
  m = c.message();
  EXPECT_EQ(m.rfind("II;tag1\n00P\n", 0), 0U) << m;
  l = lines_of(m);
  ASSERT_TRUE(scip::parse_info_reply(l, scip::Command::II, "LASR", value, sizeof value, why));
  EXPECT_STREQ(value, "OFF");
}

TEST_F(ScipServerTest, LaserCommandsAndErrorsGetTheirStatus) {
  Client c(server_.port());
  c.send_line("BM");
  EXPECT_EQ(c.message(), "BM\n00P\n\n");
  c.send_line("BM");
  EXPECT_EQ(c.message(), "BM\n02R\n\n");  // already on
  c.send_line("QT");
  EXPECT_EQ(c.message(), "QT\n00P\n\n");
  c.send_line("GD0000108001");
  EXPECT_EQ(c.message(), "GD0000108001\n10" + std::string(1, scip::checksum("10", 2)) + "\n\n");
  c.send_line("RS");
  EXPECT_EQ(c.message(), "RS\n00P\n\n");
  c.send_line("XY");
  EXPECT_EQ(c.message(), "XY\n0Ee\n\n");
  c.send_line("MD0000108101000");  // end step beyond AMAX
  EXPECT_EQ(c.message(), "MD0000108101000\n04" + std::string(1, scip::checksum("04", 2)) + "\n\n");
  c.send_line("MD0100005001000");  // end before start
  EXPECT_EQ(c.message().substr(16, 2), "05");
  EXPECT_GE(server_.commands(), 8U);
}

TEST_F(ScipServerTest, StreamsScansWithRemainingCountsAndTimestamps) {
  Client c(server_.port());
  c.send_line("MD0000108001002;x");  // two scans
  EXPECT_EQ(c.message(), "MD0000108001002;x\n00P\n\n");
  const hal::LaserScan scan = ust_shape();
  std::vector<std::uint32_t> v(2048);
  std::uint32_t last_stamp = 0;
  for (int k = 0; k < 2; ++k) {
    server_.publish(scan);
    const std::string m = c.message();
    ASSERT_FALSE(m.empty());
    EXPECT_EQ(m.rfind("MD000010800100" + std::to_string(1 - k) + ";x\n99b\n", 0), 0U) << k;
    scip::Lines l = lines_of(m);
    scip::Distances d;
    ASSERT_EQ(scip::parse_distances(l, v.data(), nullptr, int(v.size()), d),
              scip::ReplyError::None);
    ASSERT_EQ(d.count, 1081);
    for (int i = 0; i < d.count; ++i)
      EXPECT_EQ(v[std::size_t(i)],
                std::uint32_t(std::lround(scan.ranges_m[std::size_t(i)] * 1000.0)));
    EXPECT_GE(d.stamp_ms, last_stamp);
    last_stamp = d.stamp_ms;
  }
  server_.publish(scan);  // the two asked for are sent: nothing more
  EXPECT_EQ(c.message(200), "");
  EXPECT_EQ(server_.scans_sent(), 2U);
}

TEST_F(ScipServerTest, ClustersGetsAndIntensities) {
  hal::LaserScan scan = ust_shape();
  scan.ranges_m[10] = 5.0F;
  scan.ranges_m[11] = std::numeric_limits<float>::infinity();
  server_.publish(scan);
  Client c(server_.port());
  c.send_line("BM");
  EXPECT_EQ(c.message(), "BM\n00P\n\n");
  c.send_line("GD0010001903");  // steps 10..19 in clusters of 3: 4 values
  std::string m = c.message();
  scip::Lines l = lines_of(m);
  std::vector<std::uint32_t> v(16), in(16);
  scip::Distances d;
  ASSERT_EQ(scip::parse_distances(l, v.data(), nullptr, 16, d), scip::ReplyError::None) << m;
  ASSERT_EQ(d.count, 4);
  EXPECT_EQ(v[0], 620U);  // the shortest valid of 5.0, +inf (code 1, not valid), 0.62
  EXPECT_EQ(v[3], 690U);
  c.send_line("ME0000000200000");
  EXPECT_EQ(c.message(), "ME0000000200000\n00P\n\n");
  server_.publish(scan);
  m = c.message();
  l = lines_of(m);
  ASSERT_EQ(scip::parse_distances(l, v.data(), in.data(), 16, d), scip::ReplyError::None) << m;
  ASSERT_EQ(d.count, 3);
  EXPECT_EQ(v[2], 520U);
  EXPECT_EQ(in[2], 1000U);
}

TEST_F(ScipServerTest, WrongShapesAreCountedAndFaultsCorruptScans) {
  hal::LaserScan small = ust_shape();
  small.count = 100;
  server_.publish(small);
  EXPECT_EQ(server_.shape_mismatches(), 1U);
  Client c(server_.port());
  c.send_line("MD0000108001000");
  c.message();
  std::vector<std::uint32_t> v(2048);
  scip::Distances d;
  auto next = [&] {
    server_.publish(ust_shape());
    const std::string m = c.message();
    scip::Lines l;
    if (!scip::split_lines(m.data(), m.size(), l)) return scip::ReplyError::Truncated;
    return scip::parse_distances(l, v.data(), nullptr, int(v.size()), d);
  };
  EXPECT_EQ(next(), scip::ReplyError::None);
  server_.inject(ScipServerFault::BadChecksum, 1);
  EXPECT_EQ(next(), scip::ReplyError::BadChecksum);
  EXPECT_EQ(next(), scip::ReplyError::None);
  server_.inject(ScipServerFault::Truncated, 1);
  EXPECT_NE(next(), scip::ReplyError::None);
  EXPECT_EQ(next(), scip::ReplyError::None);
}

TEST_F(ScipServerTest, PublishNeverWaitsForTheClient) {
  // A client that asks for scans and never reads: publish() stays a copy into a buffer.
  Client c(server_.port());
  c.send_line("MD0000108001000");
  const hal::LaserScan scan = ust_shape();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 2000; ++i) server_.publish(scan);
  const auto dt = std::chrono::steady_clock::now() - t0;
  EXPECT_LT(std::chrono::duration_cast<std::chrono::milliseconds>(dt).count(), 200);
  server_.stop();  // and stopping does not hang on the stalled client
  EXPECT_FALSE(server_.running());
}

}  // namespace
}  // namespace carril::sim
