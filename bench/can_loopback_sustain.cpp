// carril_can_loopback_sustain: the in-process LoopbackCanBus carrying classic CAN's worst-case
// line rate at 1 Mbit/s (7,407 frames/s: 8-byte frames of 135 bits) in real time, with a
// CanLogTap on the receiving node drained by a writer thread, as `--can-log` does. Every 1 ms
// period it sends the frames due, lets the bus transfer them and receives them all; at the end it
// prints the rate reached and every loss (send refused, receive overrun, frames missing or out of
// order, log records dropped) and exits 1 unless there were none.
// Usage: carril_can_loopback_sustain [--seconds 60] [--rate 7407] [--log FILE]
#include <pthread.h>
#include <time.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "hal/can/CanLogTap.hpp"
#include "hal/can/LoopbackCanBus.hpp"

namespace {

using carril::hal::TimeNs;

TimeNs mono_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return TimeNs(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
TimeNs wall_ns(void*) {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return TimeNs(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace carril::hal;
  double seconds = 60;
  long rate = 7407;
  const char* log_path = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--rate") == 0 && i + 1 < argc) {
      rate = std::atol(argv[++i]);
    } else if (std::strcmp(argv[i], "--log") == 0 && i + 1 < argc) {
      log_path = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--seconds S] [--rate FRAMES_PER_S] [--log FILE]\n", argv[0]);
      return 2;
    }
  }
  if (!(seconds > 0) || rate <= 0) {
    std::fprintf(stderr, "carril_can_loopback_sustain: --seconds and --rate must be positive\n");
    return 2;
  }
  constexpr TimeNs kPeriod = 1'000'000;  // 1 ms, a control period
  LoopbackCanBus::Config cfg;
  cfg.tx_depth = 32;  // per node; at 7,407 frames/s about 8 are due each period
  cfg.rx_depth = 64;
  LoopbackCanBus bus(cfg);
  CanLogTap tap(bus.endpoint(1), 4096, "vcan0", &wall_ns, nullptr);
  FILE* log = log_path != nullptr ? std::fopen(log_path, "w") : nullptr;
  if (log_path != nullptr && log == nullptr) {
    std::fprintf(stderr, "carril_can_loopback_sustain: cannot write %s\n", log_path);
    return 2;
  }
  std::atomic<bool> stop{false};
  std::uint64_t lines = 0;
  std::thread writer([&] {  // the slow thread: drains the tap every 10 ms
    const auto write = [&](const char* s, std::size_t n) {
      if (log != nullptr) std::fwrite(s, 1, n, log);
      ++lines;
    };
    while (!stop.load()) {
      tap.drain(write);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    tap.drain(write);
  });

  const long total = long(double(rate) * seconds);
  long sent = 0, refused = 0, received = 0, out_of_order = 0, late_periods = 0;
  TimeNs worst_period_ns = 0;
  const TimeNs t0 = mono_ns();
  TimeNs t_last_send = t0;
  TimeNs next = t0;
  CanFrame f, got;
  f.len = 8;
  while (sent < total || received < sent) {
    next += kPeriod;
    const TimeNs start = mono_ns();
    // Frames due by now at the rate, counted from t0 (no drift).
    const long due = std::min<long>(total, long((start - t0) * rate / 1'000'000'000) + 1);
    const auto take_all = [&] {
      bus.transfer();
      while (tap.receive(got)) {
        long seq = 0;
        std::memcpy(&seq, got.data, sizeof seq);
        if (seq != received) ++out_of_order;
        ++received;
      }
    };
    while (sent < due) {
      f.id = 0x180U + std::uint32_t(sent & 0x7F);
      std::memcpy(f.data, &sent, sizeof sent);
      // After a late wake-up more than a queue's worth is due: the bus drains meanwhile, as a
      // real one would at its line rate. A frame refused after that is a loss.
      if (!bus.endpoint(0).send(f)) {
        take_all();
        if (!bus.endpoint(0).send(f)) {
          ++refused;
          break;
        }
      }
      if (++sent == total) t_last_send = mono_ns();
    }
    take_all();
    const TimeNs busy = mono_ns() - start;
    if (busy > worst_period_ns) worst_period_ns = busy;
    if (mono_ns() > next) ++late_periods;
    const timespec ts{time_t(next / 1'000'000'000), long(next % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    if (sent >= total && received < sent && mono_ns() - t0 > TimeNs(seconds * 2e9)) break;
  }
  // The rate over the sending time: the last frame was due at total / rate.
  const double dt = double(t_last_send - t0) * 1e-9;
  stop = true;
  writer.join();
  if (log != nullptr) std::fclose(log);
  const CanBusCounters tx = bus.endpoint(0).counters(), rx = bus.endpoint(1).counters();
  // tx.tx_dropped counts first tries refused for a full queue and sent again after the bus
  // drained (late wake-ups): not losses, reported apart.
  const std::uint64_t losses = std::uint64_t(refused) + rx.rx_dropped +
                               std::uint64_t(sent - received) + std::uint64_t(out_of_order) +
                               tap.dropped() + (tap.recorded() - lines);
  std::printf(
      "loopback: %ld frames in %.3f s = %.1f frames/s (asked %ld) | send refused %ld (queue full, "
      "sent "
      "again after the bus drained: %llu), rx_dropped %llu, missing %ld, out of order %ld, log "
      "lines %llu, log dropped %llu | "
      "worst period %.1f us of %lld, late periods %ld | %s\n",
      received, dt, double(received) / dt, rate, refused,
      static_cast<unsigned long long>(tx.tx_dropped),
      static_cast<unsigned long long>(rx.rx_dropped), sent - received, out_of_order,
      static_cast<unsigned long long>(lines), static_cast<unsigned long long>(tap.dropped()),
      double(worst_period_ns) * 1e-3, static_cast<long long>(kPeriod / 1000), late_periods,
      losses == 0 && received == total ? "zero drops" : "LOSSES");
  return losses == 0 && received == total ? 0 : 1;
}
