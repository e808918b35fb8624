// The CANopen master's cost (issue 9 item 10, docs/performance.md):
//  - BM_FrameCodec: encode one RPDO1 and decode one TPDO1, the per-frame protocol work;
//  - BM_ControlCycle4Drives: one whole control period of CanopenWheelDrives::sync() for 4 drives
//    at steady state: read and dispatch what one period brings (4 TPDO1, 4 TPDO2, and the drives'
//    heartbeats of the recorded period: they beat every other period), heartbeat
//    consumer, 4 power state machines, send 4 RPDO1, SYNC and the master heartbeat. The frames
//    are recorded from a real exchange with 4 emulated drives and replayed, so only the master
//    is timed. Per frame = cycle time / frames in and out (reported as a counter).
// Run: ./build/host/bench/bench_canopen --benchmark_repetitions=9
//        --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"
#include "hal/canopen/Frames.hpp"
#include "host_sim/drives/DriveEmulator.hpp"

namespace {

using namespace carril;
using hal::TimeNs;
constexpr TimeNs kMs = 1'000'000;
constexpr int kWheels = 4;

class FakeClock final : public hal::Clock {
 public:
  TimeNs now_ns() const override { return t; }
  TimeNs cpu_now_ns() const override { return t; }
  void sleep_until_ns(TimeNs until) override { t = std::max(t, until); }
  TimeNs t = 0;
};

// Live: forwards to the loopback endpoint and records what the master receives. Replay: hands out
// the recorded period's frames again and swallows what the master sends.
class RecordReplayBus final : public hal::CanBus {
 public:
  explicit RecordReplayBus(hal::CanBus& live) : live_(live) {}
  bool send(const hal::CanFrame& f) override {
    if (replay_) {
      ++sent_;
      return true;
    }
    return live_.send(f);
  }
  bool receive(hal::CanFrame& out) override {
    if (replay_) {
      if (next_ >= period_.size()) return false;
      out = period_[next_++];
      return true;
    }
    if (!live_.receive(out)) return false;
    if (recording_) period_.push_back(out);
    return true;
  }
  hal::CanBusCounters counters() const override { return live_.counters(); }

  void record() {
    period_.clear();
    recording_ = true;
  }
  void replay() {
    recording_ = false;
    replay_ = true;
  }
  void rewind() { next_ = 0; }
  std::size_t frames_per_period() const { return period_.size(); }
  std::uint64_t sent() const { return sent_; }

 private:
  hal::CanBus& live_;
  std::vector<hal::CanFrame> period_;
  std::size_t next_ = 0;
  bool recording_ = false;
  bool replay_ = false;
  std::uint64_t sent_ = 0;
};

struct Rig : hal::canopen::BringUpWaiter {
  hal::LoopbackCanBus bus{[] {
    hal::LoopbackCanBus::Config c;
    c.endpoints = 1 + kWheels;
    c.tx_depth = 128;
    c.rx_depth = 256;
    return c;
  }()};
  FakeClock clock;
  RecordReplayBus port{bus.endpoint(0)};
  std::unique_ptr<sim::DriveEmulator> drive[kWheels];
  std::unique_ptr<hal::canopen::CanopenWheelDrives> master;

  Rig() {
    hal::canopen::CanopenConfig c;
    c.wheels = kWheels;
    for (int i = 0; i < kWheels; ++i) {
      c.drive[i].node = static_cast<std::uint8_t>(1 + i);
      c.drive[i].units = hal::cia402::DriveUnits{4096.0, 12.52};
      c.drive[i].heartbeat_ms = 20;  // a heartbeat every other period
      sim::DriveEmulator::Config e;
      e.node = c.drive[i].node;
      e.units = c.drive[i].units;
      drive[i] = std::make_unique<sim::DriveEmulator>(bus.endpoint(1 + i), e);
    }
    c.heartbeat_consumer_ns = 35 * kMs;  // + 2 periods within 3 heartbeat periods
    c.control_period_ns = 10 * kMs;
    master = std::make_unique<hal::canopen::CanopenWheelDrives>(port, clock, *this, c);
  }
  void wait(TimeNs until) override {
    while (clock.t < until) physics();
  }
  void physics() {
    clock.t += kMs;
    bus.transfer();
    for (auto& d : drive) d->step(clock.t, 1e-3);
    bus.transfer();
  }
  void period() {
    master->sync();
    for (int k = 0; k < 10; ++k) physics();
  }
  // Up, enabled, turning; then one steady period's received frames recorded.
  bool prepare() {
    const hal::DriveInitResult r = master->init();
    if (!r.ok) {
      std::fprintf(stderr, "bring-up: %s\n", r.what);
      return false;
    }
    master->enable();
    const float sp[kWheels] = {3.0F, 3.0F, 3.0F, 3.0F};
    for (int k = 0; k < 50; ++k) {
      master->set_velocity(sp, kWheels);
      period();
    }
    port.record();
    period();
    port.replay();
    return true;
  }
};

void BM_FrameCodec(benchmark::State& state) {
  std::uint16_t sw = 0;
  std::int32_t v = 0;
  std::int32_t target = 1000;
  for (auto _ : state) {
    hal::CanFrame out = hal::canopen::rpdo1(3, 0x000F, target);
    benchmark::DoNotOptimize(out);
    hal::CanFrame in = out;
    in.id = 0x183;  // as a TPDO1 of node 3
    const bool ok = hal::canopen::decode_tpdo1(in, 3, sw, v);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(v);
    ++target;
  }
  state.counters["frames"] = benchmark::Counter(double(state.iterations()) * 2.0,
                                                benchmark::Counter::kIsRate |
                                                    benchmark::Counter::kInvert);
}
BENCHMARK(BM_FrameCodec);

void BM_ControlCycle4Drives(benchmark::State& state) {
  Rig rig;
  if (!rig.prepare()) {
    state.SkipWithError("bring-up failed");
    return;
  }
  const float sp[kWheels] = {3.0F, 3.0F, 3.0F, 3.0F};
  const std::uint64_t sent0 = rig.port.sent();
  for (auto _ : state) {
    rig.clock.t += 10 * kMs;
    rig.port.rewind();
    rig.master->set_velocity(sp, kWheels);
    rig.master->sync();
  }
  const double frames_in = double(rig.port.frames_per_period());
  const double frames_out = double(rig.port.sent() - sent0) / double(state.iterations());
  state.counters["frames_in"] = frames_in;
  state.counters["frames_out"] = frames_out;
  // Time per frame handled: the cycle's time over the frames it read and sent [s per frame].
  state.counters["per_frame"] =
      benchmark::Counter(double(state.iterations()) * (frames_in + frames_out),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  if (rig.master->counters().faults != 0) state.SkipWithError("the master latched a fault");
}
BENCHMARK(BM_ControlCycle4Drives);

}  // namespace

BENCHMARK_MAIN();
