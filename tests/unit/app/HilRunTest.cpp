// HilRun (carril_sim --hil) on the loopback bus against the real CANopen master: the world moves
// as the master commands through the emulated drives (mirrored mountings from the controller
// file included), and an injected heartbeat silence becomes the master's fault.
#include "host_sim/app/HilRun.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <unistd.h>

#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"
#include "hal/linux/ShmSensorLink.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"
#include "loader/ControllerLoader.hpp"

namespace carril::sim {
namespace {

using hal::TimeNs;
constexpr TimeNs kMs = 1'000'000;

class FakeClock final : public hal::Clock {
 public:
  TimeNs now_ns() const override { return t; }
  TimeNs cpu_now_ns() const override { return t; }
  void sleep_until_ns(TimeNs until) override { t = std::max(t, until); }
  TimeNs t = 0;
};

struct Rig : hal::canopen::BringUpWaiter {
  Scenario scenario;
  HilConfig cfg;
  hal::LoopbackCanBus wire{[] {
    hal::LoopbackCanBus::Config c;
    c.tx_depth = 256;
    c.rx_depth = 512;
    return c;
  }()};
  FakeClock clock;
  std::unique_ptr<HilRun> hil;
  std::unique_ptr<hal::canopen::CanopenWheelDrives> master;

  explicit Rig(const std::vector<std::string>& injections = {}) {
    const LoadResult loaded = load_scenario(
        std::string(CARRIL_SOURCE_DIR) + "/scenarios/circle.yaml", default_robots_dir(), {});
    EXPECT_TRUE(loaded.ok) << loaded.error;
    scenario = loaded.scenario;
    std::string error;
    EXPECT_TRUE(loader::load_controller(
        std::string(CARRIL_SOURCE_DIR) + "/config/controller/campero_hil.yaml", scenario.robot,
        cfg.controller, error))
        << error;
    cfg.scip_port = 0;  // no sockets in a unit test
    cfg.shm_name.clear();
    for (const std::string& text : injections) {
      HilInjection inj;
      EXPECT_TRUE(parse_injection(text, 4, inj, error)) << error;
      cfg.injections.push_back(inj);
    }
    hil = std::make_unique<HilRun>(scenario, 1, wire.endpoint(1), cfg);
    EXPECT_TRUE(hil->open(error)) << error;
    hal::canopen::CanopenConfig c;
    c.wheels = 4;
    for (int i = 0; i < 4; ++i) {
      const loader::ControllerDriveSpec& d = cfg.controller.can.drives[std::size_t(i)];
      c.drive[i].node = static_cast<std::uint8_t>(d.node);
      c.drive[i].units = hal::cia402::DriveUnits{d.counts_per_rev, d.gear_ratio};
      c.drive[i].inverted = d.inverted;
      c.drive[i].heartbeat_ms = static_cast<std::uint16_t>(cfg.controller.can.drive_heartbeat_ms);
      c.drive[i].master_timeout_ms =
          static_cast<std::uint16_t>(cfg.controller.can.master_timeout_ms);
    }
    c.master_heartbeat_ns = cfg.controller.can.master_heartbeat_ms * kMs;
    c.heartbeat_consumer_ns = cfg.controller.can.drive_timeout_ms * kMs;
    master = std::make_unique<hal::canopen::CanopenWheelDrives>(wire.endpoint(0), clock, *this, c);
  }
  // The world runs (10 ms steps) while the master waits.
  void wait(TimeNs until) override {
    while (clock.t < until) world();
  }
  void world() {
    clock.t += 10 * kMs;
    wire.transfer();
    hil->step(0.01);
    wire.transfer();
  }
  void period() {
    master->sync();
    world();
  }
};

TEST(HilRun, TheWorldMovesAsTheMasterCommandsThroughTheEmulatedDrives) {
  Rig r;
  const hal::DriveInitResult up = r.master->init();
  ASSERT_TRUE(up.ok) << up.what;
  r.master->enable();
  const float sp[4] = {2.0F, 2.0F, 2.0F, 2.0F};  // every wheel forward: straight ahead
  const Pose2 p0 = r.hil->pose();
  const double t0 = r.hil->sim_time_s();
  for (int k = 0; k < 300; ++k) {
    r.master->set_velocity(sp, 4);
    r.period();
  }
  const Pose2 p1 = r.hil->pose();
  const double dx = (p1.x - p0.x) * std::cos(p0.yaw_rad) + (p1.y - p0.y) * std::sin(p0.yaw_rad);
  // 2 rad/s x 0.127 m = 0.254 m/s for 3 s, less the ramp: forward, not sideways or turning
  // (the mirrored right-hand drives turn their motors backwards).
  EXPECT_NEAR(dx, 0.254 * (r.hil->sim_time_s() - t0), 0.12);
  EXPECT_NEAR(p1.yaw_rad, p0.yaw_rad, 0.05);
  EXPECT_LT(r.hil->drive(1).wheel_speed_radps(), -1.9);  // the motor of a mirrored drive
  EXPECT_GT(r.hil->drive(0).wheel_speed_radps(), 1.9);
  EXPECT_GT(r.hil->sync_rate_hz(), 95.0);
  EXPECT_GT(r.hil->tpdo_rate_hz(), 4 * 2 * 95.0);
  EXPECT_EQ(r.hil->metrics().collisions(), 0);
}

TEST(HilRun, AnInjectedHeartbeatSilenceBecomesTheMastersFaultAndEveryWheelStops) {
  Rig r({"4:2:heartbeat_silence"});
  ASSERT_TRUE(r.master->init().ok);
  r.master->enable();
  const float sp[4] = {2.0F, 2.0F, 2.0F, 2.0F};
  while (r.hil->sim_time_s() < 6.0) {
    r.master->set_velocity(sp, 4);
    r.period();
  }
  hal::WheelFeedbackSet fb;
  r.master->read(fb);
  EXPECT_EQ(fb.wheel[2].state, hal::DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(fb.wheel[2].fault), 0x8130);
  EXPECT_LT(r.hil->max_wheel_speed(), 0.01);
  const std::string json = r.hil->summary_json();
  EXPECT_NE(json.find("\"what\": \"4:2:heartbeat_silence\", \"applied\": true"), std::string::npos)
      << json;
}

// The IMU in shared memory reads as the simulator's gyro does (GyroSim: the robot file's bias
// and noise on the true yaw rate), not the truth: the controller's odometry takes its heading
// from it, and a noise-free gyro would make hardware-in-the-loop runs better than a real robot.
TEST(HilRun, TheSharedMemoryImuCarriesTheRobotsGyroErrors) {
  Rig r;
  r.hil.reset();
  r.cfg.shm_name = "/carril_test_hil_gyro_" + std::to_string(getpid());
  r.hil = std::make_unique<HilRun>(r.scenario, 1, r.wire.endpoint(1), r.cfg);
  std::string error;
  ASSERT_TRUE(r.hil->open(error)) << error;
  hal::ShmSensorReader reader;
  ASSERT_TRUE(reader.open(r.cfg.shm_name.c_str())) << reader.error();
  ASSERT_GT(r.scenario.robot.imu.gyro_noise_std_radps, 0.0);
  // Drives never enabled: the robot stands still, its true yaw rate 0.
  double sum = 0.0, sum2 = 0.0;
  int n = 0, distinct = 0;
  float last = 0.0F;
  for (int k = 0; k < 400; ++k) {
    r.world();
    const hal::ImuSample s = reader.imu().read();
    if (!s.valid) continue;
    distinct += n > 0 && s.yaw_rate_radps != last ? 1 : 0;
    last = s.yaw_rate_radps;
    sum += s.yaw_rate_radps;
    sum2 += double(s.yaw_rate_radps) * s.yaw_rate_radps;
    ++n;
  }
  ASSERT_GT(n, 300);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_GT(distinct, n / 2);
  EXPECT_NEAR(mean, r.scenario.robot.imu.gyro_bias_radps, 4.0 * sd / std::sqrt(double(n)));
  EXPECT_NEAR(sd, r.scenario.robot.imu.gyro_noise_std_radps, 0.25 * sd);
}

TEST(HilRun, ABadInjectionIsNamed) {
  HilInjection inj;
  std::string why;
  EXPECT_FALSE(parse_injection("4:7:heartbeat_silence", 4, inj, why));
  EXPECT_EQ(why, "drive: expected a wheel index 0 to 3 or all, got \"7\"");
  EXPECT_FALSE(parse_injection("4:all:fault:0xZZ", 4, inj, why));
  EXPECT_NE(why.find("what: expected heartbeat_silence"), std::string::npos) << why;
  EXPECT_FALSE(parse_injection("soon:1:bus_silence", 4, inj, why));
  EXPECT_EQ(why, "time: expected seconds >= 0, got \"soon\"");
  ASSERT_TRUE(parse_injection("2.5:all:corrupt:3", 4, inj, why)) << why;
  EXPECT_EQ(inj.drive, -1);
  EXPECT_EQ(inj.count, 3);
  EXPECT_DOUBLE_EQ(inj.t_s, 2.5);
}

}  // namespace
}  // namespace carril::sim
