// The SCIP 2.0 lidar client against the simulator's SCIP server over localhost TCP.
#include "hal/linux/ScipLidar.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "host_sim/hil/ScipServer.hpp"

namespace carril::hal {
namespace {

constexpr double kDeg = M_PI / 180.0;
using Ms = std::chrono::milliseconds;

LaserScan shape() {
  LaserScan s;
  s.count = 541;  // 270 deg in 0.5 deg steps
  s.angle_min_rad = float(-135.0 * kDeg);
  s.angle_increment_rad = float(0.5 * kDeg);
  s.range_min_m = 0.05F;
  s.range_max_m = 20.0F;
  for (int i = 0; i < s.count; ++i) s.ranges_m[std::size_t(i)] = 0.3F + 0.0137F * float(i);
  return s;
}

// The simulator's side: publishes `scan` every 10 ms on its own thread.
class Publisher {
 public:
  Publisher(sim::ScipServer& s, const LaserScan& scan)
      : t_([&s, scan, this] {
          while (!stop_) {
            s.publish(scan);
            std::this_thread::sleep_for(Ms(10));
          }
        }) {}
  ~Publisher() {
    stop_ = true;
    t_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread t_;
};

sim::ScipServerConfig server_config(std::uint16_t port) {
  sim::ScipServerConfig c;
  const char* why = "";
  EXPECT_TRUE(sim::ScipServer::geometry_for(shape(), 1200, c.geometry, why)) << why;
  c.port = port;
  return c;
}

ScipLidarConfig lidar_config(std::uint16_t port) {
  ScipLidarConfig c;
  c.host = "127.0.0.1";
  c.port = port;
  c.data_timeout_ns = 1'000'000'000;  // generous: other builds share the cores
  c.backoff_min_ns = 20'000'000;
  c.backoff_max_ns = 100'000'000;
  return c;
}

// Waits up to 3 s for pred().
template <class P>
bool eventually(P pred) {
  for (int i = 0; i < 300; ++i) {
    if (pred()) return true;
    std::this_thread::sleep_for(Ms(10));
  }
  return pred();
}

TEST(ScipLidar, ReadsTheServedScanWithinMillimetresAndRep117Specials) {
  LaserScan served = shape();
  const float inf = std::numeric_limits<float>::infinity();
  served.ranges_m[3] = inf;
  served.ranges_m[4] = -inf;
  served.ranges_m[5] = std::numeric_limits<float>::quiet_NaN();
  served.ranges_m[6] = 0.0F;
  served.ranges_m[7] = 45.0F;  // out of limit (beyond range_max): passed through
  served.ranges_m[8] = 0.01F;  // closer than range_min
  sim::ScipServer server;
  ASSERT_TRUE(server.start(server_config(0))) << server.error();
  Publisher pub(server, served);
  ScipLidar lidar;
  EXPECT_EQ(lidar.latest(), nullptr);
  ASSERT_TRUE(lidar.start(lidar_config(server.port()))) << lidar.error();
  ASSERT_TRUE(eventually([&] { return lidar.latest() != nullptr; })) << lidar.last_problem();
  const LaserScan& got = *lidar.latest();
  EXPECT_GE(got.seq, 1U);
  ASSERT_EQ(got.count, served.count);
  EXPECT_NEAR(got.angle_min_rad, served.angle_min_rad, 1e-6);
  EXPECT_NEAR(got.angle_increment_rad, served.angle_increment_rad, 1e-7);
  EXPECT_FLOAT_EQ(got.range_min_m, 0.05F);
  EXPECT_FLOAT_EQ(got.range_max_m, 20.0F);
  // Half a millimetre (the wire's resolution) plus the float rounding of a few metres.
  for (int i = 9; i < served.count; ++i)
    EXPECT_NEAR(got.ranges_m[std::size_t(i)], served.ranges_m[std::size_t(i)], 0.0005 + 2e-6) << i;
  EXPECT_EQ(got.ranges_m[3], inf);
  EXPECT_EQ(got.ranges_m[4], -inf);
  EXPECT_TRUE(std::isnan(got.ranges_m[5]));
  EXPECT_EQ(got.ranges_m[6], 0.0F);
  EXPECT_FLOAT_EQ(got.ranges_m[7], 45.0F);
  EXPECT_EQ(got.ranges_m[8], -inf);
  const scip::Geometry g = lidar.geometry();
  EXPECT_EQ(g.ares, 720);
  EXPECT_EQ(g.afrt, 270);
  EXPECT_TRUE(lidar.connected());
  EXPECT_EQ(lidar.malformed(), 0U);
  // Scans keep coming, each with a new seq.
  const std::uint32_t seq = got.seq;
  ASSERT_TRUE(eventually([&] { return lidar.latest()->seq > seq + 2; }));
  lidar.stop();
}

TEST(ScipLidar, MalformedScansAreCountedAndDropped) {
  sim::ScipServer server;
  ASSERT_TRUE(server.start(server_config(0))) << server.error();
  Publisher pub(server, shape());
  ScipLidar lidar;
  ASSERT_TRUE(lidar.start(lidar_config(server.port())));
  ASSERT_TRUE(eventually([&] { return lidar.scans() > 0; }));
  server.inject(sim::ScipServerFault::BadChecksum, 3);
  ASSERT_TRUE(eventually([&] { return lidar.malformed() >= 3; }));
  server.inject(sim::ScipServerFault::Truncated, 2);
  ASSERT_TRUE(eventually([&] { return lidar.malformed() >= 5; }));
  const std::uint32_t scans = lidar.scans();
  ASSERT_TRUE(eventually([&] { return lidar.scans() > scans + 2; }));  // and it goes on
  EXPECT_EQ(lidar.malformed(), 5U);
  EXPECT_EQ(lidar.connects(), 1U);  // without reconnecting
  // Every published scan is whole.
  EXPECT_EQ(lidar.latest()->count, 541);
}

TEST(ScipLidar, ReconnectsAfterTheServerRestarts) {
  auto server = std::make_unique<sim::ScipServer>();
  ASSERT_TRUE(server->start(server_config(0))) << server->error();
  const std::uint16_t port = server->port();
  auto pub = std::make_unique<Publisher>(*server, shape());
  ScipLidar lidar;
  ASSERT_TRUE(lidar.start(lidar_config(port)));
  ASSERT_TRUE(eventually([&] { return lidar.scans() > 0; }));
  pub.reset();
  server.reset();  // the sensor goes away
  ASSERT_TRUE(eventually([&] { return !lidar.connected(); }));
  const std::uint32_t seq = lidar.latest()->seq;
  std::this_thread::sleep_for(Ms(100));
  EXPECT_EQ(lidar.latest()->seq, seq);  // stale: the last scan stays, nothing new
  EXPECT_EQ(lidar.disconnects(), 1U);

  server = std::make_unique<sim::ScipServer>();
  ASSERT_TRUE(server->start(server_config(port))) << server->error();
  pub = std::make_unique<Publisher>(*server, shape());
  ASSERT_TRUE(eventually([&] { return lidar.connects() == 2 && lidar.latest()->seq > seq; }))
      << lidar.last_problem();
}

TEST(ScipLidar, ASilentSensorIsDroppedAndReconnected) {
  sim::ScipServer server;
  ASSERT_TRUE(server.start(server_config(0)));
  Publisher pub(server, shape());
  ScipLidar lidar;
  ScipLidarConfig c = lidar_config(server.port());
  c.data_timeout_ns = 200'000'000;
  ASSERT_TRUE(lidar.start(c));
  ASSERT_TRUE(eventually([&] { return lidar.scans() > 0; }));
  server.inject(sim::ScipServerFault::Silent, 40);  // 400 ms of no scans > data timeout
  ASSERT_TRUE(eventually([&] { return lidar.disconnects() >= 1; }));
  EXPECT_STREQ(lidar.last_problem(), "no scan within data_timeout_ns");
  ASSERT_TRUE(eventually([&] { return lidar.connects() >= 2; }));
  EXPECT_GE(server.clients(), 2U);
}

TEST(ScipLidar, BadConfigAndNoSensorAreReportedNotFatal) {
  ScipLidar lidar;
  ScipLidarConfig c = lidar_config(1);
  c.host = "lidar.local";
  EXPECT_FALSE(lidar.start(c));
  EXPECT_NE(std::string(lidar.error()).find("'lidar.local' is not an IPv4"), std::string::npos);
  c = lidar_config(1);
  c.backoff_max_ns = 1;
  EXPECT_FALSE(lidar.start(c));
  // Nobody listens on port 1: refused, retried, and latest() stays empty.
  ASSERT_TRUE(lidar.start(lidar_config(1)));
  std::this_thread::sleep_for(Ms(100));
  EXPECT_EQ(lidar.latest(), nullptr);
  EXPECT_STREQ(lidar.last_problem(), "connection refused or timed out");
  EXPECT_FALSE(lidar.connected());
}

}  // namespace
}  // namespace carril::hal
